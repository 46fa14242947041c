"""A spinning LiDAR (rings and returns a revolution from the config or a sensor file): rays from
the sensor origin, vectorised ray-triangle tests, and foliage volumes that rays enter.

Because every ray starts at the sensor, the Moller-Trumbore terms that do not depend on the ray
are computed once per triangle and the rest are three matrix products per object. Objects are
culled to the window of rows and columns their bounding volume can reach, and within it to the
rays that cross their bounding box before anything nearer.
"""
import dataclasses

import numpy as np

from . import meshes

ROAD_REFLECTIVITY = 0.10
LANE_MARKING_REFLECTIVITY = 0.65
VERGE_REFLECTIVITY = 0.22


@dataclasses.dataclass
class PlacedMesh:
    """A mesh in the sensor frame with its own paint reflectivity."""
    vertices: np.ndarray
    faces: np.ndarray
    materials: np.ndarray
    reflectivity: float


@dataclasses.dataclass
class Volume:
    """Foliage as a volume of leaves, axis-aligned in the sensor frame: an ellipsoid (a tree's
    canopy) or a box (a hedge). A ray that enters it returns after a free path drawn from an
    exponential distribution of mean 1 / density, unless it leaves the volume first: returns
    come from throughout the volume, and some rays pass through."""
    centre: np.ndarray          # m
    half_size: np.ndarray       # m, semi-axes of the ellipsoid, half extents of the box
    is_box: bool
    density: float              # 1/m, leaves met per metre of ray
    material: int = meshes.FOLIAGE


# Leaves face every way: the mean |cos| of the incidence angle on randomly oriented surfaces.
LEAF_COS_INCIDENCE = 0.5


@dataclasses.dataclass
class Returns:
    points: np.ndarray        # (N, 3) float64, sensor frame
    intensity: np.ndarray     # (N,) uint8


class Lidar:
    def __init__(self, config):
        self.config = config
        half_fov = np.radians(config.vertical_fov_deg) / 2.0
        centre = np.radians(config.vertical_centre_deg)
        self.elevations = np.linspace(centre - half_fov, centre + half_fov, config.lasers)
        self.azimuth_step = 2.0 * np.pi / config.measurements_per_revolution
        self.azimuths = np.arange(config.measurements_per_revolution) * self.azimuth_step
        # Directions in firing order: for each azimuth, every laser (as a Velodyne streams them).
        az, el = np.meshgrid(self.azimuths, self.elevations, indexing="ij")
        self.directions = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az),
                                    np.sin(el)], axis=-1)  # (columns, rows, 3)

    def scan(self, placed_meshes, ground_reflectivity, rng, volumes=()):
        """Cast every ray; return the first hits within range, with noise and dropouts.

        `ground_reflectivity(x, y)` gives the road's reflectivity at sensor-frame positions;
        `volumes` (Volume) are foliage that a ray may pass through.
        """
        cfg = self.config
        columns, rows = self.directions.shape[:2]
        hit_range = np.full((columns, rows), np.inf)
        reflectivity = np.zeros((columns, rows))
        cos_incidence = np.ones((columns, rows))
        dropout = np.zeros((columns, rows))

        self._cast_ground(ground_reflectivity, hit_range, reflectivity, cos_incidence)
        # Nearest first, so that rays already stopped closer than an object skip its triangles.
        for mesh in sorted(placed_meshes, key=lambda placed: _distance_to_box(placed.vertices)):
            window = self._window(mesh.vertices)
            if window is None:
                continue
            col_idx, row_idx = window
            sub = np.ix_(col_idx, row_idx)
            flat_cols = np.repeat(col_idx, len(row_idx))
            flat_rows = np.tile(row_idx, len(col_idx))
            current = hit_range[sub].reshape(-1)
            low, high = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
            # Only rays that cross the mesh's bounding box (1 mm wider, against rounding) before
            # their current hit can hit one of its triangles first.
            enter, leave = _box_span(self.directions[sub].reshape(-1, 3), (low + high) / 2.0,
                                     (high - low) / 2.0 + 1e-3)
            reachable = (leave >= np.maximum(enter, 0.0)) & (enter < current)
            if not np.any(reachable):
                continue
            flat_cols, flat_rows = flat_cols[reachable], flat_rows[reachable]
            directions = self.directions[flat_cols, flat_rows]
            t, face = _first_hits(directions, mesh.vertices, mesh.faces)
            closer = t < current[reachable]
            if not np.any(closer):
                continue
            flat_cols, flat_rows = flat_cols[closer], flat_rows[closer]
            faces_hit = face[closer]
            hit_range[flat_cols, flat_rows] = t[closer]
            materials = mesh.materials[faces_hit]
            refl = meshes.REFLECTIVITY[materials]
            reflectivity[flat_cols, flat_rows] = np.where(np.isnan(refl), mesh.reflectivity, refl)
            dropout[flat_cols, flat_rows] = meshes.EXTRA_DROPOUT[materials]
            normals = _face_normals(mesh.vertices, mesh.faces[faces_hit])
            cos_incidence[flat_cols, flat_rows] = np.abs(
                np.einsum("ij,ij->i", normals, directions[closer]))
        for volume in volumes:
            self._cast_volume(volume, rng, hit_range, reflectivity, cos_incidence, dropout)

        hit_range = hit_range.reshape(-1)
        measured = hit_range + rng.normal(0.0, cfg.range_noise_sigma, hit_range.shape)
        intensity = 255.0 * reflectivity.reshape(-1) * (0.3 + 0.7 * cos_incidence.reshape(-1))
        intensity *= 1.0 + rng.normal(0.0, 0.05, intensity.shape)
        intensity = np.clip(np.rint(intensity), 0, 255)
        lost = rng.random(hit_range.shape) < cfg.dropout_probability + dropout.reshape(-1)
        keep = (np.isfinite(hit_range) & (measured >= cfg.min_range)
                & (measured <= cfg.max_range) & ~lost & (intensity >= cfg.min_return_intensity))
        points = self.directions.reshape(-1, 3)[keep] * measured[keep, None]
        return Returns(points, intensity[keep].astype(np.uint8))

    def _cast_ground(self, ground_reflectivity, hit_range, reflectivity, cos_incidence):
        """The road plane at z = -mount_height; lane markings and verges reflect differently."""
        dz = self.directions[..., 2]
        down = dz < -1e-6
        t = np.where(down, -self.config.mount_height / np.where(down, dz, -1.0), np.inf)
        hit_range[...] = t
        with np.errstate(invalid="ignore"):
            x = np.nan_to_num(t * self.directions[..., 0], posinf=0.0, neginf=0.0)
            y = np.nan_to_num(t * self.directions[..., 1], posinf=0.0, neginf=0.0)
        reflectivity[...] = ground_reflectivity(x, y)
        cos_incidence[...] = np.abs(dz)

    def _cast_volume(self, volume, rng, hit_range, reflectivity, cos_incidence, dropout):
        """Returns from inside a foliage volume, where they come before the surfaces hit so far."""
        corners = volume.centre + volume.half_size * np.array(
            [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
        window = self._window(corners)
        if window is None:
            return
        col_idx, row_idx = window
        sub = np.ix_(col_idx, row_idx)
        directions = self.directions[sub].reshape(-1, 3)
        enter, leave = _volume_span(directions, volume)
        # One free path per ray of the window, drawn whether or not the ray enters, so the
        # number of draws depends on the geometry only.
        at = np.maximum(enter, 0.0) + rng.exponential(1.0 / volume.density, len(directions))
        returned = (at < leave) & (at < hit_range[sub].reshape(-1))
        if not np.any(returned):
            return
        cols = np.repeat(col_idx, len(row_idx))[returned]
        rows = np.tile(row_idx, len(col_idx))[returned]
        hit_range[cols, rows] = at[returned]
        reflectivity[cols, rows] = meshes.REFLECTIVITY[volume.material]
        dropout[cols, rows] = meshes.EXTRA_DROPOUT[volume.material]
        cos_incidence[cols, rows] = LEAF_COS_INCIDENCE

    def _window(self, vertices):
        """Columns and rows whose rays can reach the vertices' bounding volume, or None."""
        centre = 0.5 * (vertices.max(axis=0) + vertices.min(axis=0))
        radius_xy = np.max(np.linalg.norm(vertices[:, :2] - centre[:2], axis=1))
        distance_xy = np.linalg.norm(centre[:2])
        if distance_xy - radius_xy > self.config.max_range:
            return None
        near, far = distance_xy - radius_xy, distance_xy + radius_xy
        if near <= 0.05:
            col_idx = np.arange(len(self.azimuths))
            near = 0.05
        else:
            # Azimuth is monotonic along any segment that misses the sensor, so the vertices
            # bound the object's angular span.
            centre_az = np.arctan2(centre[1], centre[0])
            rel = np.angle(np.exp(1j * (np.arctan2(vertices[:, 1], vertices[:, 0]) - centre_az)))
            first = int(np.floor((centre_az + rel.min()) / self.azimuth_step))
            last = int(np.ceil((centre_az + rel.max()) / self.azimuth_step))
            col_idx = np.arange(first, last + 1) % len(self.azimuths)
        # Elevation is not monotonic along a segment, so bound it with the height range and the
        # nearest and farthest horizontal distance of the footprint.
        z_low, z_high = vertices[:, 2].min(), vertices[:, 2].max()
        el_high = np.arctan2(z_high, near if z_high > 0 else far)
        el_low = np.arctan2(z_low, near if z_low < 0 else far)
        row_idx = np.nonzero((self.elevations >= el_low - 1e-9)
                             & (self.elevations <= el_high + 1e-9))[0]
        if len(row_idx) == 0:
            return None
        return col_idx, row_idx


def _distance_to_box(vertices):
    """Distance from the sensor to the vertices' axis-aligned bounding box (0 inside it)."""
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    return float(np.linalg.norm(np.maximum(np.maximum(low, -high), 0.0)))


def _box_span(directions, centre, half_size):
    """Distances at which rays from the origin enter and leave an axis-aligned box (slabs:
    per axis the ray is between the two faces for t in [near, far]; a miss: leave < enter, or
    leave < 0 for a box behind the sensor)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        first = (centre - half_size) / directions
        second = (centre + half_size) / directions
    near, far = np.minimum(first, second), np.maximum(first, second)
    # A ray parallel to a slab is inside it for every t, or for none.
    inside = np.abs(centre) <= half_size
    parallel = directions == 0.0
    near = np.where(parallel, np.where(inside, -np.inf, np.inf), near)
    far = np.where(parallel, np.where(inside, np.inf, -np.inf), far)
    return near.max(axis=1), far.min(axis=1)


def _volume_span(directions, volume):
    """Distances at which rays from the origin enter and leave a volume (a miss: leave < enter,
    or leave < 0 for a volume behind the sensor)."""
    if volume.is_box:
        return _box_span(directions, volume.centre, volume.half_size)
    with np.errstate(divide="ignore", invalid="ignore"):
        # Ellipsoid: scaled to the unit sphere, |p + t q| = 1 with p the origin, q the direction.
        p = -volume.centre / volume.half_size
        q = directions / volume.half_size
        a = np.einsum("ij,ij->i", q, q)
        b = 2.0 * (q @ p)
        c = p @ p - 1.0
        discriminant = b * b - 4.0 * a * c
        root = np.sqrt(np.maximum(discriminant, 0.0))
        enter, leave = (-b - root) / (2.0 * a), (-b + root) / (2.0 * a)
        missed = discriminant <= 0.0
        return np.where(missed, np.inf, enter), np.where(missed, -np.inf, leave)


def _cross(a, b):
    """Row-wise cross product of (N, 3) arrays: numpy's own arithmetic without np.cross's
    per-call overhead, which dominated for the many small meshes of a parking lot."""
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
                     a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def _face_normals(vertices, faces):
    normals = _cross(vertices[faces[:, 1]] - vertices[faces[:, 0]],
                       vertices[faces[:, 2]] - vertices[faces[:, 0]])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return normals / np.where(length > 0.0, length, 1.0)


def _first_hits(directions, vertices, faces):
    """Distance to the first triangle along each ray from the origin, and that triangle's index.

    Moller-Trumbore with the ray origin at 0: s = -v0 and q = s x e1 are per triangle, and
    det = e1.(d x e2), u = s.(d x e2), v = d.q are rewritten as d.(...) for all rays at once.
    """
    v0 = vertices[faces[:, 0]]
    e1 = vertices[faces[:, 1]] - v0
    e2 = vertices[faces[:, 2]] - v0
    s = -v0
    q = _cross(s, e1)
    det = directions @ _cross(e2, e1).T          # d . (e2 x e1) = e1 . (d x e2)
    u_num = directions @ _cross(e2, s).T         # s . (d x e2) = d . (e2 x s)
    v_num = directions @ q.T
    t_num = np.einsum("ij,ij->i", e2, q)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        u, v, t = u_num * inv, v_num * inv, t_num[None, :] * inv
        valid = (np.abs(det) > 1e-12) & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 1e-6)
    t = np.where(valid, t, np.inf)
    face = np.argmin(t, axis=1)
    return t[np.arange(len(t)), face], face
