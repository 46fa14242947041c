"""ROS messages built and read in one place: the LGSVL simulator's point layout, clouds and
Detection3DArrays from arrays (the simulator, kitti_to_bag), from PCD files and detections JSON
(frames_player, the labelling tool), and the x, y, z and boxes of any cloud and detection."""
import typing

import genpy
import numpy as np
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3
from lgsvl_msgs.msg import BoundingBox3D, Detection3D, Detection3DArray
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header

from .geometry import Cuboid
from .pcd import read_pcd

# The LGSVL LiDAR's point layout: x y z float32, intensity uint8, timestamp float64.
POINT_DTYPE = np.dtype({"names": ["x", "y", "z", "intensity", "timestamp"],
                        "formats": ["<f4", "<f4", "<f4", "u1", "<f8"],
                        "offsets": [0, 4, 8, 16, 24], "itemsize": 32})
POINT_FIELDS = [PointField("x", 0, PointField.FLOAT32, 1),
                PointField("y", 4, PointField.FLOAT32, 1),
                PointField("z", 8, PointField.FLOAT32, 1),
                PointField("intensity", 16, PointField.UINT8, 1),
                PointField("timestamp", 24, PointField.FLOAT64, 1)]


class LabelledBox(typing.NamedTuple):
    """One box of a Detection3DArray to write: centre (m), quaternion (x, y, z, w), size (length,
    width, height), speed along its own x axis (m/s). The simulator's scene.Detection has the
    same fields."""
    object_id: int
    label: str
    position: typing.Sequence[float]
    quaternion: typing.Sequence[float]
    size: typing.Sequence[float]
    forward_speed: float = 0.0


def ros_time(start_time, t):
    """The ROS time `t` seconds after `start_time` (s since the epoch), to the nanosecond."""
    nanoseconds = int(round(start_time * 1e9)) + int(round(t * 1e9))
    return genpy.Time(nanoseconds // 1_000_000_000, nanoseconds % 1_000_000_000)


def cloud_message(points, intensity, stamp, frame_id, seq):
    """A PointCloud2 in the LGSVL layout of `points` (N, 3) and `intensity` (N,) uint8."""
    record = np.zeros(len(points), dtype=POINT_DTYPE)
    for axis, name in enumerate("xyz"):
        record[name] = points[:, axis]
    record["intensity"] = intensity
    # A snapshot at one instant, so every point carries the cloud's stamp.
    record["timestamp"] = stamp.to_sec()
    return PointCloud2(header=Header(seq=seq, stamp=stamp, frame_id=frame_id), height=1,
                       width=len(record), fields=POINT_FIELDS, is_bigendian=False,
                       point_step=POINT_DTYPE.itemsize, row_step=POINT_DTYPE.itemsize * len(record),
                       data=record.tobytes(), is_dense=True)


def detections_message(boxes, stamp, frame_id, seq):
    """A Detection3DArray of `boxes` (LabelledBox, or anything with its fields), score 1."""
    header = Header(seq=seq, stamp=stamp, frame_id=frame_id)
    message = Detection3DArray(header=header)
    for box in boxes:
        message.detections.append(Detection3D(
            header=header, id=box.object_id, label=box.label, score=1.0,
            bbox=BoundingBox3D(position=Pose(Point(*box.position), Quaternion(*box.quaternion)),
                               size=Vector3(*box.size)),
            velocity=Twist(linear=Vector3(box.forward_speed, 0.0, 0.0),
                           angular=Vector3(0.0, 0.0, 0.0))))
    return message


def dict_to_detections(document):
    """The report's JSON back into a Detection3DArray (the inverse of
    frames_folder.detections_to_dict)."""
    def header(h):
        return Header(seq=h.get("seq", 0), frame_id=h.get("frame_id", ""),
                      stamp=genpy.Time(h["stamp"]["secs"], h["stamp"]["nsecs"]))

    def vector(v, kind=Vector3):
        return kind(v["x"], v["y"], v["z"])

    message = Detection3DArray(header=header(document["header"]))
    for d in document["detections"]:
        pose = d["bbox"]["position"]
        o = pose["orientation"]
        message.detections.append(Detection3D(
            header=header(d["header"]), id=d["id"], label=d["label"], score=d["score"],
            bbox=BoundingBox3D(position=Pose(vector(pose["position"], Point),
                                             Quaternion(o["x"], o["y"], o["z"], o["w"])),
                               size=vector(d["bbox"]["size"])),
            velocity=Twist(vector(d["velocity"]["linear"]), vector(d["velocity"]["angular"]))))
    return message


def pcd_to_cloud(path, frame_id, stamp):
    """Read a PCD file into a PointCloud2 with the file's fields."""
    fields, points, width, height = read_pcd(path)
    return PointCloud2(header=Header(stamp=stamp, frame_id=frame_id), height=height, width=width,
                       fields=fields, is_bigendian=False, point_step=points.dtype.itemsize,
                       row_step=points.dtype.itemsize * width, data=points.tobytes(),
                       is_dense=False)


def cloud_xyz(message):
    """x, y, z of a PointCloud2 as float64 (N, 3), whatever the field offsets."""
    offsets = {field.name: field.offset for field in message.fields}
    missing = [axis for axis in "xyz" if axis not in offsets]
    if missing:
        raise ValueError(f"cloud has no field(s) {', '.join(missing)}")
    dtype = np.dtype({"names": list("xyz"), "formats": ["<f4"] * 3,
                      "offsets": [offsets[a] for a in "xyz"], "itemsize": message.point_step})
    points = np.frombuffer(message.data, dtype=dtype, count=message.width * message.height)
    return np.stack([points[a] for a in "xyz"], axis=1).astype(float)


def detection_cuboid(detection):
    """The Cuboid of a Detection3D's box."""
    pose, size = detection.bbox.position, detection.bbox.size
    o = pose.orientation
    return Cuboid((pose.position.x, pose.position.y, pose.position.z), (size.x, size.y, size.z),
                  (o.x, o.y, o.z, o.w))
