"""Boxes and rotations, written once for every tool: the Cuboid, quaternions to matrices and
back, quaternion products, yaw, rotated footprints, bird's-eye and 3-D IoU, points in a box.

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
    """The 3x3 rotation of a unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def quaternion_from_matrix(rotation):
    """(x, y, z, w), w >= 0, of a rotation matrix (Shepperd's method: stable for every angle)."""
    m = np.asarray(rotation, float)
    trace = np.trace(m)
    if trace > max(m[0, 0], m[1, 1], m[2, 2]):
        s = 2.0 * math.sqrt(1.0 + trace)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0] * 4
        q[i], q[j], q[k] = s / 4, (m[j, i] + m[i, j]) / s, (m[k, i] + m[i, k]) / s
        q[3] = (m[k, j] - m[j, k]) / s
    q = np.array(q) / np.linalg.norm(q)
    return tuple(float(v) for v in (-q if q[3] < 0.0 else q))


def quaternion_multiply(a, b):
    """The quaternion product a b, both (x, y, z, w): b's rotation, then a's."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def rotate(q, v):
    """The vector `v` (3,) turned by the unit quaternion `q` (x, y, z, w)."""
    x, y, z, w = q
    u = np.array([x, y, z])
    v = np.asarray(v, float)
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


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
