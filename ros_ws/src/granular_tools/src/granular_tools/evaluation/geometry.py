"""Cuboid geometry for evaluate_cuboids: yaw, rotated footprints, bird's-eye and 3-D IoU.

A cuboid is the `bbox` of a Detection3D: centre, orientation (quaternion x, y, z, w) and size
(x = length along the box's heading, y = width, z = height), in metres. Overlaps treat a box
as upright: its footprint is the size.x by size.y rectangle turned by the yaw of its x axis
about z, its vertical extent centre z +- size.z / 2. Roll and pitch are ignored, which is exact
for upright boxes and close for boxes tilted by a few degrees (docs/cuboids.md). Polygon
intersections are shapely's (exact for these convex polygons up to rounding).
"""
import dataclasses
import math

import numpy as np
from shapely.geometry import Polygon


@dataclasses.dataclass(frozen=True)
class Cuboid:
    """An oriented box; `quaternion` is (x, y, z, w) and unit length."""
    centre: tuple
    size: tuple
    quaternion: tuple = (0.0, 0.0, 0.0, 1.0)

    @property
    def yaw(self):
        """Heading of the box's x axis in the x-y plane, radians in (-pi, pi]."""
        return yaw_of_quaternion(self.quaternion)

    def rotation(self):
        return rotation_matrix(self.quaternion)

    def z_range(self):
        half = self.size[2] / 2.0
        return self.centre[2] - half, self.centre[2] + half

    def volume(self):
        return self.size[0] * self.size[1] * self.size[2]


def from_yaw(x, y, z, length, width, height, yaw):
    """An upright cuboid turned by `yaw` (radians) about z."""
    return Cuboid((x, y, z), (length, width, height),
                  (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)))


def rotation_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def yaw_of_quaternion(q):
    """The heading of the rotated x axis projected on the x-y plane (radians): the yaw of a
    roll-pitch-yaw rotation, whatever the roll and pitch."""
    x, y, z, w = q
    return math.atan2(2 * (x * y + z * w), 1 - 2 * (y * y + z * z))


def yaw_difference_deg(a, b, period=180.0):
    """|a - b| (radians in, degrees out) modulo `period` degrees, in [0, period / 2]: with
    the default 180 a box turned half a turn counts as the same box."""
    difference = math.degrees(a - b) % period
    return min(difference, period - difference)


def footprint(box):
    """The 4 corners (x, y) of the box's bird's-eye rectangle, counter-clockwise."""
    c, s = math.cos(box.yaw), math.sin(box.yaw)
    half_l, half_w = box.size[0] / 2.0, box.size[1] / 2.0
    local = np.array([[half_l, half_w], [-half_l, half_w], [-half_l, -half_w],
                      [half_l, -half_w]])
    return local @ np.array([[c, s], [-s, c]]) + np.array(box.centre[:2])


def bev_intersection(a, b):
    """Area (m^2) common to the two footprints."""
    return Polygon(footprint(a)).intersection(Polygon(footprint(b))).area


def bev_iou(a, b):
    """Bird's-eye IoU: footprint intersection over union."""
    common = bev_intersection(a, b)
    union = a.size[0] * a.size[1] + b.size[0] * b.size[1] - common
    return common / union if union > 0 else 0.0


def z_overlap(a, b):
    (a_low, a_high), (b_low, b_high) = a.z_range(), b.z_range()
    return max(0.0, min(a_high, b_high) - max(a_low, b_low))


def iou_3d(a, b):
    """3-D IoU of the boxes taken as upright: footprint intersection times z overlap."""
    common = bev_intersection(a, b) * z_overlap(a, b)
    union = a.volume() + b.volume() - common
    return common / union if union > 0 else 0.0


def count_points_inside(xyz, box):
    """How many rows of `xyz` (N x 3) lie inside the box, full orientation (roll, pitch, yaw)."""
    if len(xyz) == 0:
        return 0
    local = (xyz - np.asarray(box.centre)) @ box.rotation()
    return int(np.count_nonzero(np.all(np.abs(local) <= np.asarray(box.size) / 2.0, axis=1)))
