"""Small hand-made bags for tests: clouds and detections at chosen stamps."""
import genpy
import numpy as np
import rosbag
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header

from granular_tools.messages import LabelledBox, cloud_message, detections_message, ros_time

CLOUD_TOPIC = "/simulator/lidar"
DETECTIONS_TOPIC = "/simulator/ground_truth/3d_detections"
START = 1586102742.0


def stamp(t):
    return ros_time(START, t)


def cloud(t, points=None, seq=0):
    points = np.array([[1.0, 2.0, -2.3], [5.0, -1.0, 0.5]]) if points is None else points
    return cloud_message(np.asarray(points, float), np.arange(len(points), dtype=np.uint8),
                         stamp(t), "velodyne", seq)


def cloud_without_xyz(t):
    return PointCloud2(header=Header(stamp=stamp(t), frame_id="velodyne"), height=1, width=1,
                       fields=[PointField("intensity", 0, PointField.FLOAT32, 1)],
                       point_step=4, row_step=4, data=b"\x00\x00\x80\x3f", is_dense=True)


def velodyne_cloud(t, points):
    """A cloud in velodyne_pointcloud's layout: x y z intensity (float32), ring (uint16), time
    (float32), 22 bytes a point."""
    fields = [PointField("x", 0, PointField.FLOAT32, 1), PointField("y", 4, PointField.FLOAT32, 1),
              PointField("z", 8, PointField.FLOAT32, 1),
              PointField("intensity", 12, PointField.FLOAT32, 1),
              PointField("ring", 16, PointField.UINT16, 1),
              PointField("time", 18, PointField.FLOAT32, 1)]
    record = np.dtype({"names": ["x", "y", "z", "intensity", "ring", "time"],
                       "formats": ["<f4", "<f4", "<f4", "<f4", "<u2", "<f4"],
                       "offsets": [0, 4, 8, 12, 16, 18], "itemsize": 22})
    points = np.asarray(points, float)
    data = np.zeros(len(points), dtype=record)
    for axis, name in enumerate("xyz"):
        data[name] = points[:, axis]
    data["intensity"] = 7.5
    data["ring"] = np.arange(len(points)) % 64
    data["time"] = np.linspace(0.0, 0.1, len(points))
    return PointCloud2(header=Header(stamp=stamp(t), frame_id="velodyne"), height=1,
                       width=len(points), fields=fields, is_bigendian=False, point_step=22,
                       row_step=22 * len(points), data=data.tobytes(), is_dense=True)


def detections(t, labels=("Sedan",), seq=0):
    boxes = [LabelledBox(100 + i, label, np.array([5.0 + i, -1.0, -1.5]), (0.0, 0.0, 0.0, 1.0),
                         np.array([4.5, 1.8, 1.4]), 3.0) for i, label in enumerate(labels)]
    return detections_message(boxes, stamp(t), "velodyne", seq)


def write(path, messages, stamp=None):
    """messages: (topic, message) in recording order; recorded at their header stamps, or at
    `stamp` for messages without a header (tf2_msgs/TFMessage)."""
    with rosbag.Bag(str(path), "w") as bag:
        for topic, message in messages:
            bag.write(topic, message, message.header.stamp if hasattr(message, "header")
                      else stamp)
    return path


def as_time(seconds):
    return genpy.Time.from_sec(seconds)
