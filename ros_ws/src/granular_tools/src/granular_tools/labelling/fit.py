"""A new box from a click on the cloud: the object's points around the click, the ground under
it, and the smallest rectangle around the points seen from above (docs/labelling.md).

1. Ground: a low percentile of the heights of every point within `ground_radius` of the click
   (x-y), so that a few returns below the road do not count as the road.
2. Object: the points between `ground_clearance` and `max_height` above the ground, within
   `max_radius` of the click (or the diagonal of the class's default footprint, if longer: a
   click anywhere on the object reaches its far corner), that connect through gaps of at most
   `gap`, seen from above, to the points within `seed_radius` of the click (so that a click on
   a roof takes the sides under it, however far apart the scan lines are).
3. Box: the minimum-area rectangle of the object's x-y (rotating calipers on the convex hull),
   from the ground up to its highest point. Rectangles within `AREA_TIE` of the smallest area
   count as tied, and the one whose edges the points lie closest to wins: an object seen on
   two sides (an L) has a right-triangle hull, whose rectangle along the hypotenuse has the
   same area as the one along the sides. Its longer side is the length, unless it matches
   the class's width better and the other side is under half that width: then the object was
   seen end on (a car from behind) and the longer side is its width.
4. A side under half the class's default is a face seen edge on: the box is grown to the
   default along that axis, away from the sensor (the frame's origin), keeping the seen face.

With fewer than `min_points` object points the box has the class's default size, on the
ground, centred on the click, along x.
"""
import dataclasses
import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull, QhullError, cKDTree

from ..config_loading import bounded
from ..evaluation.geometry import Cuboid
from .boxes import face_centre, rotation_about_z, with_face_dragged
from ..kitti import quaternion_from_matrix

AREA_TIE = 1.1  # rectangles up to 10 % larger than the smallest count as tied


@dataclasses.dataclass(frozen=True)
class FitSettings:
    seed_radius: float = bounded(1.5, above=0.0)  # m (x-y): the object's point nearest the click
    max_radius: float = bounded(4.0, above=0.0)  # m (x-y) from the click: no object point farther
    gap: float = bounded(0.8, above=0.0)  # m: points closer than this belong to one object
    ground_radius: float = bounded(6.0, above=0.0)  # m (x-y): points that tell where the ground is
    ground_percentile: float = bounded(5.0, at_least=0.0, at_most=100.0)  # % of heights below it
    ground_clearance: float = bounded(0.25, at_least=0.0)  # m above the ground: not the road
    max_height: float = bounded(4.5, above=0.0)  # m above the ground: not a tree or a bridge
    min_points: int = bounded(10, at_least=1)  # fewer object points: the class's default box


@dataclasses.dataclass(frozen=True)
class Fit:
    box: Cuboid
    points: int  # object points the box was fitted to; 0 when it has the default size
    ground: float  # z of the ground under the click, m


def minimum_area_rectangle(xy):
    """(centre (2,), (side along angle, side across), angle in rad) of the smallest rectangle
    holding the points `xy` (N x 2), one of whose sides lies on an edge of their convex hull;
    near ties go to the rectangle whose edges the points lie closest to (see the module)."""
    xy = np.asarray(xy, float)
    try:
        hull = xy[ConvexHull(xy).vertices]
    except (QhullError, ValueError):  # fewer than 3 points, or all on one line
        hull = xy
    edges = np.diff(np.vstack([hull, hull[:1]]), axis=0)
    angles = np.unique(np.arctan2(edges[:, 1], edges[:, 0]) % (math.pi / 2.0))
    candidates = []
    for angle in angles if len(angles) else [0.0]:
        c, s = math.cos(angle), math.sin(angle)
        local = xy @ np.array([[c, -s], [s, c]])  # the points in the frame turned by `angle`
        low, high = local.min(axis=0), local.max(axis=0)
        to_edge = np.minimum(local - low, high - local).min(axis=1)
        middle = (low + high) / 2.0
        candidates.append((float(np.prod(high - low)), float(to_edge.mean()),
                           np.array([c * middle[0] - s * middle[1], s * middle[0] + c * middle[1]]),
                           tuple(float(v) for v in high - low), float(angle)))
    smallest = min(area for area, *_ in candidates)
    tied = [c for c in candidates if c[0] <= smallest * AREA_TIE]
    _, _, centre, sides, angle = min(tied, key=lambda c: c[1])
    return centre, sides, angle


def _object_points(xyz, click, ground, radius, settings):
    """The connected object points nearest the click (see the module), possibly none."""
    horizontal = np.hypot(xyz[:, 0] - click[0], xyz[:, 1] - click[1])
    height = xyz[:, 2] - ground
    candidates = xyz[(horizontal <= radius) & (height > settings.ground_clearance)
                     & (height < settings.max_height)]
    if len(candidates) == 0:
        return candidates
    seeds = np.hypot(candidates[:, 0] - click[0],
                     candidates[:, 1] - click[1]) <= settings.seed_radius
    pairs = cKDTree(candidates[:, :2]).query_pairs(settings.gap, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])),
                       shape=(len(candidates),) * 2)
    _, component = connected_components(graph, directed=False)
    return candidates[np.isin(component, component[seeds])]


def _upright_box(centre_xy, bottom, size, yaw):
    length, width, height = size
    return Cuboid((float(centre_xy[0]), float(centre_xy[1]), float(bottom + height / 2.0)),
                  (float(length), float(width), float(height)),
                  quaternion_from_matrix(rotation_about_z(yaw)))


def _grow_away_from_sensor(box, axis, target):
    """`box` grown to `target` m along `axis` (0 length, 1 width), its face nearer the sensor
    (the origin) kept."""
    plus, minus = ("+x", "-x") if axis == 0 else ("+y", "-y")
    far = plus if np.hypot(*face_centre(box, plus)[:2]) > np.hypot(*face_centre(box, minus)[:2]) \
        else minus
    grown, _ = with_face_dragged(box, far, target - box.size[axis], min_size=0.0)
    return grown


def fit_box_at_click(xyz, click, default_size, settings=FitSettings()):
    """The Fit for a click at `click` (x, y, z) on the cloud `xyz` (N x 3, finite) for a class
    of default size (length, width, height)."""
    xyz = np.asarray(xyz, float).reshape(-1, 3)
    near = xyz[np.hypot(xyz[:, 0] - click[0], xyz[:, 1] - click[1]) <= settings.ground_radius]
    ground = float(np.percentile(near[:, 2], settings.ground_percentile)) if len(near) \
        else float(click[2])
    default_length, default_width, default_height = default_size
    reach = max(settings.max_radius, math.hypot(default_length, default_width))
    points = _object_points(xyz, click, ground, reach, settings)
    if len(points) < settings.min_points:
        return Fit(_upright_box(click[:2], ground, default_size, 0.0), 0, ground)

    centre, (along, across), angle = minimum_area_rectangle(points[:, :2])
    long_side, short_side = max(along, across), min(along, across)
    long_angle = angle if along >= across else angle + math.pi / 2.0
    seen_end_on = abs(long_side - default_width) < abs(long_side - default_length) \
        and short_side < default_width / 2.0
    if seen_end_on:
        length, width, yaw = short_side, long_side, long_angle + math.pi / 2.0
    else:
        length, width, yaw = long_side, short_side, long_angle
    yaw = (yaw + math.pi / 2.0) % math.pi - math.pi / 2.0  # heading ambiguous: keep it in [-90, 90)
    height = float(points[:, 2].max()) - ground
    if height < default_height / 2.0:
        height = default_height
    box = _upright_box(centre, ground, (length, width, height), yaw)
    for axis, default in ((0, default_length), (1, default_width)):
        if box.size[axis] < default / 2.0:
            box = _grow_away_from_sensor(box, axis, default)
    return Fit(box, len(points), ground)
