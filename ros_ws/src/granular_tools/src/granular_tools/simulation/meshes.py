"""Triangle meshes for every simulated class, clutter, and user-supplied mesh files.

Meshes are in the object frame: metres, x forward, y left, z up, origin at the centre of the
axis-aligned bounding box, so that the box a detection reports is the mesh's bounding box.
"""
import dataclasses
import os

import numpy as np

# Surface materials and their LiDAR reflectivity (0-1). PAINT takes the instance's own colour.
PAINT, GLASS, TYRE, METAL, CONCRETE, FOLIAGE, CLOTH, BARK = range(8)
REFLECTIVITY = np.array([np.nan, 0.08, 0.04, 0.45, 0.3, 0.22, 0.3, 0.25])
# Glass lets part of the beams through, so windows have holes as in real scans.
EXTRA_DROPOUT = np.array([0.0, 0.35, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0])

VEHICLE_CLASSES = ("Sedan", "SUV", "Hatchback", "Jeep", "BoxTruck", "SchoolBus")
CLASSES = VEHICLE_CLASSES + ("Pedestrian",)


class MeshError(ValueError):
    """A mesh file that cannot be used; the message names the file."""


@dataclasses.dataclass
class Mesh:
    vertices: np.ndarray   # (V, 3) float64
    faces: np.ndarray      # (F, 3) int64 vertex indices
    materials: np.ndarray  # (F,) int64 material per face

    @property
    def extents(self):
        return self.vertices.max(axis=0) - self.vertices.min(axis=0)

    def centred(self):
        """The same mesh moved so that its bounding box is centred on the origin."""
        centre = 0.5 * (self.vertices.max(axis=0) + self.vertices.min(axis=0))
        return Mesh(self.vertices - centre, self.faces, self.materials)

    def scaled(self, factors):
        return Mesh(self.vertices * np.asarray(factors, dtype=float), self.faces, self.materials)


def merge(meshes):
    vertices, faces, materials, offset = [], [], [], 0
    for mesh in meshes:
        vertices.append(mesh.vertices)
        faces.append(mesh.faces + offset)
        materials.append(mesh.materials)
        offset += len(mesh.vertices)
    return Mesh(np.vstack(vertices), np.vstack(faces), np.concatenate(materials))


def _fan(ring):
    """Triangles closing a convex ring of vertex indices."""
    return [(ring[0], ring[k], ring[k + 1]) for k in range(1, len(ring) - 1)]


def loft(stations, glass_slope=0.5):
    """A vehicle body lofted through cross-sections along x.

    Each station is (x, z_bottom, z_belt, z_top, half_width, roof_half_width): the body is full
    width up to the belt line, above it the greenhouse narrows to the roof. Side faces above the
    belt and steep top faces (windscreens, rear windows) are glass.
    """
    ring_size = 6
    vertices = []
    for x, z_bottom, z_belt, z_top, half_width, roof_half_width in stations:
        vertices += [(x, -half_width, z_bottom), (x, half_width, z_bottom),
                     (x, half_width, z_belt), (x, roof_half_width, z_top),
                     (x, -roof_half_width, z_top), (x, -half_width, z_belt)]
    faces, materials = [], []
    for i in range(len(stations) - 1):
        (x0, _, belt0, top0, _, _), (x1, _, belt1, top1, _, _) = stations[i], stations[i + 1]
        has_greenhouse = top0 > belt0 + 0.05 or top1 > belt1 + 0.05
        steep = abs(top1 - top0) > glass_slope * abs(x1 - x0)
        for j in range(ring_size):
            a, b = i * ring_size + j, i * ring_size + (j + 1) % ring_size
            c, d = b + ring_size, a + ring_size
            faces += [(a, b, c), (a, c, d)]
            is_window = j in (2, 4) and has_greenhouse
            is_screen = j == 3 and has_greenhouse and steep
            materials += [GLASS if is_window or is_screen else PAINT] * 2
    last = (len(stations) - 1) * ring_size
    for ring in (list(range(ring_size))[::-1], list(range(last, last + ring_size))):
        caps = _fan(ring)
        faces += caps
        materials += [PAINT] * len(caps)
    return Mesh(np.array(vertices, float), np.array(faces), np.array(materials))


def prism(outline, sweep, offset, material):
    """A prism whose convex 2-D cross-section `outline` is swept along a coordinate axis.

    `sweep` is (axis, start, end) with axis 0, 1 or 2; the two remaining axes, in order, take the
    outline's coordinates shifted by `offset`.
    """
    axis, start, end = sweep
    outline = np.asarray(outline, float)
    other = [k for k in range(3) if k != axis]
    n = len(outline)
    vertices = np.zeros((2 * n, 3))
    for half, position in enumerate((start, end)):
        vertices[half * n:(half + 1) * n, other[0]] = outline[:, 0] + offset[0]
        vertices[half * n:(half + 1) * n, other[1]] = outline[:, 1] + offset[1]
        vertices[half * n:(half + 1) * n, axis] = position
    faces = []
    for k in range(n):
        a, b = k, (k + 1) % n
        faces += [(a, b, b + n), (a, b + n, a + n)]
    faces += _fan(list(range(n))[::-1]) + _fan(list(range(n, 2 * n)))
    return Mesh(vertices, np.array(faces), np.full(len(faces), material))


def polygon(radius, sides=8):
    angles = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    return np.stack([radius * np.cos(angles), radius * np.sin(angles)], axis=1)


def box(centre, size, material):
    cx, cy, cz = centre
    sx, sy, sz = np.asarray(size) / 2.0
    outline = [(cy - sy, cz - sz), (cy + sy, cz - sz), (cy + sy, cz + sz), (cy - sy, cz + sz)]
    return prism(outline, (0, cx - sx, cx + sx), (0.0, 0.0), material)


def wheels(axle_xs, half_track, radius=0.33, width=0.22):
    """Tyres as octagonal prisms with their axes along y."""
    parts = []
    for x in axle_xs:
        for side in (-1.0, 1.0):
            y_outer = side * half_track
            y_inner = y_outer - side * width
            parts.append(prism(polygon(radius), (1, min(y_inner, y_outer), max(y_inner, y_outer)),
                               (x, radius), TYRE))
    return parts


def _vehicle(stations, axle_xs, half_track, extras=()):
    return merge([loft(stations)] + wheels(axle_xs, half_track) + list(extras)).centred()


def sedan():
    # A trunk: the roof ends well ahead of the tail and a low deck follows.
    hw, rw = 0.91, 0.72
    return _vehicle([(-2.30, 0.35, 0.85, 0.85, hw - 0.05, rw), (-2.15, 0.30, 0.98, 0.98, hw, rw),
                     (-1.45, 0.28, 1.00, 1.00, hw, rw), (-0.75, 0.28, 0.98, 1.42, hw, rw),
                     (0.35, 0.28, 0.98, 1.45, hw, rw), (1.15, 0.28, 0.98, 0.98, hw, rw),
                     (2.10, 0.30, 0.80, 0.80, hw, rw), (2.30, 0.35, 0.62, 0.62, hw - 0.05, rw)],
                    (-1.40, 1.35), hw - 0.02)


def hatchback():
    # A flat rear: the roof runs to the tail, which drops almost vertically.
    hw, rw = 0.89, 0.72
    return _vehicle([(-2.05, 0.35, 0.95, 1.00, hw - 0.04, rw), (-1.95, 0.30, 0.97, 1.42, hw, rw),
                     (-1.75, 0.28, 0.97, 1.50, hw, rw), (0.35, 0.28, 0.97, 1.50, hw, rw),
                     (1.10, 0.28, 0.98, 0.98, hw, rw), (1.90, 0.30, 0.82, 0.82, hw, rw),
                     (2.05, 0.35, 0.60, 0.60, hw - 0.04, rw)],
                    (-1.30, 1.25), hw - 0.02)


def suv():
    hw, rw = 0.97, 0.82
    return _vehicle([(-2.40, 0.42, 1.05, 1.10, hw - 0.04, rw), (-2.30, 0.40, 1.05, 1.72, hw, rw),
                     (-2.10, 0.40, 1.05, 1.80, hw, rw), (0.60, 0.40, 1.05, 1.80, hw, rw),
                     (1.30, 0.40, 1.10, 1.10, hw, rw), (2.25, 0.42, 1.02, 1.02, hw, rw),
                     (2.40, 0.45, 0.75, 0.75, hw - 0.04, rw)],
                    (-1.45, 1.45), hw - 0.02)


def jeep():
    # Boxy: upright windscreen, flat hood, square rear with a spare wheel.
    hw, rw = 0.95, 0.88
    spare = prism(polygon(0.36), (0, -2.32, -2.10), (0.0, 1.05), TYRE)
    return _vehicle([(-2.10, 0.45, 1.10, 1.83, hw, rw), (0.50, 0.45, 1.10, 1.85, hw, rw),
                     (0.75, 0.45, 1.12, 1.12, hw, rw), (2.00, 0.45, 1.10, 1.10, hw, rw),
                     (2.10, 0.48, 0.80, 0.80, hw - 0.03, rw)],
                    (-1.25, 1.30), hw + 0.03, extras=[spare])


def box_truck():
    hw = 1.17
    cab = loft([(1.60, 0.50, 1.50, 2.60, hw, hw - 0.08), (3.20, 0.50, 1.50, 2.60, hw, hw - 0.08),
                (3.45, 0.50, 1.45, 1.45, hw, hw - 0.08), (3.60, 0.50, 1.20, 1.20, hw - 0.05, hw)])
    cargo = box((-1.05, 0.0, 2.10), (5.10, 2 * hw + 0.06, 2.40), PAINT)
    return merge([cab, cargo] + wheels((-2.40, -1.20, 2.60), hw - 0.05, radius=0.45)).centred()


def school_bus():
    hw, rw = 1.25, 1.20
    return _vehicle([(-5.50, 0.45, 1.70, 3.00, hw, rw), (3.80, 0.45, 1.70, 3.10, hw, rw),
                     (4.10, 0.45, 1.60, 1.60, hw, rw), (5.40, 0.50, 1.45, 1.45, hw, rw),
                     (5.50, 0.55, 1.20, 1.20, hw - 0.05, rw)],
                    (-3.20, 3.40), hw - 0.05)


def pedestrian():
    parts = [box((0.0, y, 0.43), (0.16, 0.14, 0.86), CLOTH) for y in (-0.10, 0.10)]
    parts += [box((0.0, 0.0, 1.16), (0.26, 0.42, 0.60), CLOTH),
              box((0.0, 0.0, 1.62), (0.20, 0.18, 0.26), PAINT)]
    parts += [box((0.02, y, 1.12), (0.11, 0.10, 0.60), CLOTH) for y in (-0.27, 0.27)]
    return merge(parts).centred()


BUILT_IN = {"Sedan": sedan, "SUV": suv, "Hatchback": hatchback, "Jeep": jeep,
            "BoxTruck": box_truck, "SchoolBus": school_bus, "Pedestrian": pedestrian}


def pole(height):
    return prism(polygon(0.12), (2, 0.0, height), (0.0, 0.0), METAL).centred()


def trunk(height, radius):
    return prism(polygon(radius), (2, 0.0, height), (0.0, 0.0), BARK).centred()


def kerb(length, width, height):
    return box((0.0, 0.0, 0.0), (length, width, height), CONCRETE)


def wall(length, height):
    return box((0.0, 0.0, 0.0), (length, 0.3, height), CONCRETE)


def shrub(radius, rng):
    """An irregular blob: a subdivided octahedron with its vertices pushed in and out."""
    vertices = np.array([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)],
                        float)
    faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    for _ in range(2):
        vertices, faces = _subdivide(vertices, faces)
    vertices /= np.linalg.norm(vertices, axis=1, keepdims=True)
    vertices *= radius * rng.uniform(0.75, 1.15, size=(len(vertices), 1))
    mesh = Mesh(vertices, np.array(faces), np.full(len(faces), FOLIAGE))
    return mesh.centred()


def _subdivide(vertices, faces):
    vertices = [tuple(v) for v in vertices]
    midpoint_index = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in midpoint_index:
            midpoint_index[key] = len(vertices)
            vertices.append(tuple((np.array(vertices[a]) + np.array(vertices[b])) / 2.0))
        return midpoint_index[key]

    new_faces = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return np.array(vertices, float), new_faces


def load_mesh_file(path):
    """Read an OBJ, PLY or STL triangle mesh (metres, x forward, z up), centred on its box."""
    import meshio  # Imported here: only users of --mesh pay for it.

    if not os.path.isfile(path):
        raise MeshError(f"{path}: mesh file not found")
    try:
        data = meshio.read(path)
    except Exception as error:  # meshio raises many types for malformed files.
        raise MeshError(f"{path}: cannot read mesh: {error}") from error
    faces = []
    for cells in data.cells:
        if cells.type == "triangle":
            faces.append(cells.data)
        elif cells.type == "quad":
            quads = cells.data
            faces += [quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]
    if not faces or len(data.points) < 3:
        raise MeshError(f"{path}: no triangles or quads in the mesh")
    vertices = np.asarray(data.points, float)[:, :3]
    if not np.all(np.isfinite(vertices)):
        raise MeshError(f"{path}: mesh has non-finite vertex coordinates")
    faces = np.vstack(faces).astype(np.int64)
    mesh = Mesh(vertices, faces, np.full(len(faces), PAINT))
    if np.any(mesh.extents <= 0.0):
        raise MeshError(f"{path}: mesh is flat (bounding box {mesh.extents.tolist()} m)")
    return mesh.centred()
