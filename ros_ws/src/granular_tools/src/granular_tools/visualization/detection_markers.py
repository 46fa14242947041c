"""MarkerArrays that draw Detection3DArray boxes: outlines coloured by label, and a text tag."""
from geometry_msgs.msg import Point, Pose, Quaternion, Vector3
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

# One colour per class, chosen to stay apart on a dark rviz background.
LABEL_COLOURS = {
    "Sedan": (0.2, 0.6, 1.0), "SUV": (0.3, 0.9, 0.3), "Hatchback": (1.0, 0.6, 0.1),
    "Jeep": (1.0, 0.25, 0.25), "BoxTruck": (0.75, 0.45, 1.0), "SchoolBus": (1.0, 0.95, 0.2),
    "Pedestrian": (0.2, 1.0, 1.0),
}
UNKNOWN_COLOUR = (0.8, 0.8, 0.8)

# The 12 edges of a unit cube centred on the origin, as pairs of corner sign vectors.
_CORNERS = [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
_EDGES = [(a, b) for a in range(8) for b in range(a + 1, 8)
          if sum(ca != cb for ca, cb in zip(_CORNERS[a], _CORNERS[b])) == 1]


def colour_of(label, alpha=1.0):
    r, g, b = LABEL_COLOURS.get(label, UNKNOWN_COLOUR)
    return ColorRGBA(r, g, b, alpha)


def detection_markers(message, lifetime, namespace="detections", colour=None):
    """Outline and label markers for every detection, coloured by label or all `colour` (r, g,
    b in [0, 1]); DELETEALL first so stale boxes go."""
    def paint(label):
        return ColorRGBA(*colour, 1.0) if colour else colour_of(label)

    markers = MarkerArray()
    markers.markers.append(Marker(header=message.header, ns=namespace, action=Marker.DELETEALL))
    for index, detection in enumerate(message.detections):
        bbox = detection.bbox
        half = (bbox.size.x / 2.0, bbox.size.y / 2.0, bbox.size.z / 2.0)
        outline = Marker(header=message.header, ns=namespace, id=2 * index,
                         type=Marker.LINE_LIST, action=Marker.ADD, pose=bbox.position,
                         scale=Vector3(0.06, 0.0, 0.0), color=paint(detection.label),
                         lifetime=lifetime)
        for a, b in _EDGES:
            for corner in (_CORNERS[a], _CORNERS[b]):
                outline.points.append(Point(*(s * h for s, h in zip(corner, half))))
        position = bbox.position.position
        text = Marker(header=message.header, ns=namespace, id=2 * index + 1,
                      type=Marker.TEXT_VIEW_FACING, action=Marker.ADD,
                      pose=Pose(Point(position.x, position.y, position.z + half[2] + 0.5),
                                Quaternion(0.0, 0.0, 0.0, 1.0)),
                      scale=Vector3(0.0, 0.0, 0.7), color=paint(detection.label),
                      text=f"{detection.label} {detection.id}", lifetime=lifetime)
        markers.markers += [outline, text]
    return markers
