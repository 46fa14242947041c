"""The edits the labelling tool makes to one cuboid: move it in the ground plane, turn it about
the vertical, push or pull one of its six faces while the opposite face stays put.

A box is a geometry.Cuboid in the cloud's frame (z up): centre, size (length,
width, height along the box's own x, y, z axes) and a unit quaternion (x, y, z, w).
"""
import math

import numpy as np

from ..geometry import Cuboid, quaternion_from_matrix, rotation_matrix

# A face is named by the box axis it faces along: "+x" is the front (the end the length
# axis points to), "-z" the bottom.
FACES = ("+x", "-x", "+y", "-y", "+z", "-z")
# Poses come back from rviz through Ogre's float32: a drag that moved a box by less than this,
# or turned it by less, is rounding, not an edit.
MOVE_TOLERANCE_M = 1e-4
TURN_TOLERANCE_RAD = 1e-4


def face_axis(face):
    """(axis index 0-2, +1 or -1) of a face name."""
    if face not in FACES:
        raise ValueError(f"unknown face {face!r} (faces: {' '.join(FACES)})")
    return "xyz".index(face[1]), 1.0 if face[0] == "+" else -1.0


def outward_normal(box, face):
    axis, sign = face_axis(face)
    return sign * box.rotation()[:, axis]


def face_centre(box, face):
    axis, _ = face_axis(face)
    return np.asarray(box.centre, float) + outward_normal(box, face) * box.size[axis] / 2.0


def moved(box, dx, dy):
    """The box moved by (dx, dy) in the ground plane; height, size and orientation kept."""
    x, y, z = box.centre
    return Cuboid((x + dx, y + dy, z), box.size, box.quaternion)


def rotation_about_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def turned(box, angle):
    """The box turned by `angle` (rad, counter-clockwise seen from above) about the vertical
    through its centre; any roll and pitch it has turn with it."""
    return Cuboid(box.centre, box.size,
                  quaternion_from_matrix(rotation_about_z(angle) @ box.rotation()))


def with_face_dragged(box, face, distance, min_size):
    """(box, distance applied): `face` moved `distance` m along its outward normal (negative:
    inwards) and the opposite face left where it was, so the centre moves by half the distance
    and the size by all of it. The box gets no thinner than `min_size` along that axis (or its
    own size, if already thinner)."""
    axis, _ = face_axis(face)
    distance = max(float(distance), min(min_size, box.size[axis]) - box.size[axis])
    size = list(box.size)
    size[axis] += distance
    centre = np.asarray(box.centre, float) + outward_normal(box, face) * distance / 2.0
    return Cuboid(tuple(float(v) for v in centre), tuple(size), box.quaternion), distance


def drag_distance(box, face, handle_position):
    """How far a face handle now at `handle_position` has been dragged from the face, along
    the face's outward normal (m)."""
    offset = np.asarray(handle_position, float) - face_centre(box, face)
    return float(offset @ outward_normal(box, face))


def yaw_change(before, after):
    """The turn about the vertical (rad, in [-pi, pi)) that takes quaternion `before` to
    `after`, both (x, y, z, w)."""
    relative = rotation_matrix(after) @ rotation_matrix(before).T
    return math.atan2(relative[1, 0], relative[0, 0])


def edited_by_pose(box, position, quaternion):
    """The box after rviz moved and turned its marker to `position` (x, y, z) and `quaternion`:
    the ground-plane part of the move and the turn about the vertical; None when the pose is
    the box's own, to rounding."""
    dx, dy = position[0] - box.centre[0], position[1] - box.centre[1]
    angle = yaw_change(box.quaternion, quaternion)
    result = box
    if math.hypot(dx, dy) >= MOVE_TOLERANCE_M:
        result = moved(result, dx, dy)
    if abs(angle) >= TURN_TOLERANCE_RAD:
        result = turned(result, angle)
    return None if result is box else result
