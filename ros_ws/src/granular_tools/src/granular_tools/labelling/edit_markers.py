"""The interactive markers of the labelling tool, built from a frame's boxes (no ROS node
needed): a box's body (drag: move in the ground plane; right click: its menu), a ring to
turn the selected box about the vertical, an arrow on each face of the selected box (drag:
move that face only), and the frame's title (click: the frame menu)."""
import math

from geometry_msgs.msg import Point, Pose, Quaternion, Vector3
from std_msgs.msg import ColorRGBA, Header
from visualization_msgs.msg import InteractiveMarker, InteractiveMarkerControl, Marker

from ..visualization.detection_markers import UNKNOWN_COLOUR
from .boxes import FACES, face_axis, face_centre

FRAME_MARKER = "frame"
HANDLE_SEPARATOR = "/"  # a face handle is "<box key>/<face>"
TITLE_HEIGHT = 2.5  # m above the sensor: the frame's title floats over the ego vehicle
TITLE_SIZE = 0.4  # m: a line's height
RING_WIDTH = 0.3  # m: the band that turns the selected box, just outside its corners
RING_SEGMENTS = 72
_HALF = math.sqrt(0.5)
# Control orientations whose x axis (the axis rviz moves along or turns about) is the box's
# x, y or z axis.
_AXIS_ORIENTATIONS = (Quaternion(0.0, 0.0, 0.0, 1.0), Quaternion(0.0, 0.0, _HALF, _HALF),
                      Quaternion(0.0, -_HALF, 0.0, _HALF))
_AXIS_COLOURS = ((1.0, 0.25, 0.25), (0.3, 1.0, 0.3), (0.35, 0.55, 1.0))  # x red, y green, z blue
# The 12 edges of a unit cube centred on the origin, as pairs of corners.
_CORNERS = [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
_EDGES = [(a, b) for a in range(8) for b in range(a + 1, 8)
          if sum(ca != cb for ca, cb in zip(_CORNERS[a], _CORNERS[b])) == 1]


def handle_name(key, face):
    return f"{key}{HANDLE_SEPARATOR}{face}"


def split_handle_name(name):
    """(box key, face) of a handle marker's name, or None for another marker."""
    key, separator, face = name.rpartition(HANDLE_SEPARATOR)
    return (key, face) if separator and face in FACES else None


def colour(rgb, alpha):
    return ColorRGBA(rgb[0], rgb[1], rgb[2], alpha)


def class_colour(label, classes):
    settings = classes.get(label)
    return tuple(settings.colour) if settings else UNKNOWN_COLOUR


def _pose(position, quaternion):
    return Pose(Point(*position), Quaternion(*quaternion))


def ring(inner_radius):
    """A flat band about the vertical through the origin, thin enough not to hide the cloud
    (rviz's default ring is as wide as a car)."""
    band = Marker(type=Marker.TRIANGLE_LIST, scale=Vector3(1.0, 1.0, 1.0),
                  color=colour((1.0, 0.8, 0.2), 0.6), pose=_pose((0, 0, 0), (0, 0, 0, 1)))
    outer = inner_radius + RING_WIDTH
    for k in range(RING_SEGMENTS):
        a, b = (2.0 * math.pi * n / RING_SEGMENTS for n in (k, k + 1))
        corners = [Point(r * math.cos(t), r * math.sin(t), 0.0)
                   for r, t in ((inner_radius, a), (outer, a), (outer, b), (inner_radius, b))]
        band.points += [corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]]
    return band


def box_marker(entry, frame_id, classes, selected, handles):
    """The body of one box: its outline, a translucent fill and its label; dragging it moves
    the box in the ground plane. The selected box also gets the ring that turns it, and its
    label rises above the top face's handle."""
    box = entry.box
    length, width, height = box.size
    rgb = class_colour(entry.detection.get("label"), classes)
    marker = InteractiveMarker(header=Header(frame_id=frame_id), name=entry.key,
                               pose=_pose(box.centre, box.quaternion), scale=1.0)
    # A faint fill: the points inside must show, but the whole body takes a click.
    fill = Marker(type=Marker.CUBE, scale=Vector3(length, width, height),
                  color=colour(rgb, 0.15 if selected else 0.08),
                  pose=_pose((0, 0, 0), (0, 0, 0, 1)))
    outline = Marker(type=Marker.LINE_LIST, scale=Vector3(0.08 if selected else 0.05, 0, 0),
                     color=colour((1.0, 1.0, 1.0) if selected else rgb, 1.0),
                     pose=_pose((0, 0, 0), (0, 0, 0, 1)))
    half = (length / 2.0, width / 2.0, height / 2.0)
    for a, b in _EDGES:
        for corner in (_CORNERS[a], _CORNERS[b]):
            outline.points.append(Point(*(s * h for s, h in zip(corner, half))))
    label = Marker(type=Marker.TEXT_VIEW_FACING, scale=Vector3(0, 0, 0.6),
                   color=colour(rgb, 1.0), text=f"{entry.detection.get('label')} "
                                                f"{entry.detection.get('id')}",
                   pose=_pose((0.0, 0.0, half[2] + 0.5 + (handles.length if selected else 0.0)),
                              (0, 0, 0, 1)))
    # Moves keep to the plane normal to the box's z axis (the ground's, for an upright box).
    body = InteractiveMarkerControl(name="move", orientation=_AXIS_ORIENTATIONS[2],
                                    orientation_mode=InteractiveMarkerControl.INHERIT,
                                    interaction_mode=InteractiveMarkerControl.MOVE_PLANE,
                                    always_visible=True, markers=[fill, outline, label])
    marker.controls.append(body)
    if selected:
        # FIXED: the ring turns the box about the frame's vertical, whatever its tilt.
        marker.controls.append(InteractiveMarkerControl(
            name="turn", orientation=_AXIS_ORIENTATIONS[2],
            orientation_mode=InteractiveMarkerControl.FIXED,
            interaction_mode=InteractiveMarkerControl.ROTATE_AXIS, always_visible=True,
            markers=[ring(math.hypot(length, width) / 2.0 + 0.2)]))
    return marker


def handle_markers(entry, frame_id, handles):
    """An arrow on each face of the box, pointing out; dragging one moves that face only."""
    markers = []
    for face in FACES:
        axis, sign = face_axis(face)
        tip = [0.0, 0.0, 0.0]
        tip[axis] = sign * handles.length
        arrow = Marker(type=Marker.ARROW, points=[Point(0, 0, 0), Point(*tip)],
                       scale=Vector3(handles.width, handles.width * 2.0, handles.width * 2.5),
                       color=colour(_AXIS_COLOURS[axis], 1.0), pose=_pose((0, 0, 0), (0, 0, 0, 1)))
        control = InteractiveMarkerControl(name="face", orientation=_AXIS_ORIENTATIONS[axis],
                                           orientation_mode=InteractiveMarkerControl.INHERIT,
                                           interaction_mode=InteractiveMarkerControl.MOVE_AXIS,
                                           always_visible=True, markers=[arrow])
        markers.append(InteractiveMarker(
            header=Header(frame_id=frame_id), name=handle_name(entry.key, face),
            pose=_pose(face_centre(entry.box, face), entry.box.quaternion), scale=1.0,
            controls=[control]))
    return markers


def title_marker(lines, frame_id, problem=False):
    """The frame's title over the sensor; clicking it opens the frame menu."""
    text = Marker(type=Marker.TEXT_VIEW_FACING, scale=Vector3(0, 0, TITLE_SIZE),
                  text="\n".join(lines),
                  color=colour((1.0, 0.35, 0.3) if problem else (1.0, 1.0, 1.0), 1.0),
                  pose=_pose((0, 0, 0), (0, 0, 0, 1)))
    control = InteractiveMarkerControl(name="menu", interaction_mode=InteractiveMarkerControl.MENU,
                                       always_visible=True, markers=[text])
    return InteractiveMarker(header=Header(frame_id=frame_id), name=FRAME_MARKER,
                             pose=_pose((0.0, 0.0, TITLE_HEIGHT), (0, 0, 0, 1)), scale=1.0,
                             controls=[control])
