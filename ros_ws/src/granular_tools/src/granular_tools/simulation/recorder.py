"""ROS messages in the LGSVL simulator's layout, written to a bag atomically."""
import genpy
import numpy as np
import rosbag
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3
from lgsvl_msgs.msg import BoundingBox3D, Detection3D, Detection3DArray
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header

from ..output import written_atomically

# The LGSVL LiDAR's point layout: x y z float32, intensity uint8, timestamp float64.
POINT_DTYPE = np.dtype({"names": ["x", "y", "z", "intensity", "timestamp"],
                        "formats": ["<f4", "<f4", "<f4", "u1", "<f8"],
                        "offsets": [0, 4, 8, 16, 24], "itemsize": 32})
POINT_FIELDS = [PointField("x", 0, PointField.FLOAT32, 1),
                PointField("y", 4, PointField.FLOAT32, 1),
                PointField("z", 8, PointField.FLOAT32, 1),
                PointField("intensity", 16, PointField.UINT8, 1),
                PointField("timestamp", 24, PointField.FLOAT64, 1)]


def ros_time(start_time, t):
    nanoseconds = int(round(start_time * 1e9)) + int(round(t * 1e9))
    return genpy.Time(nanoseconds // 1_000_000_000, nanoseconds % 1_000_000_000)


def cloud_message(returns, stamp, frame_id, seq):
    points = np.zeros(len(returns.points), dtype=POINT_DTYPE)
    for axis, name in enumerate("xyz"):
        points[name] = returns.points[:, axis]
    points["intensity"] = returns.intensity
    # A snapshot at one instant, so every point carries the cloud's stamp.
    points["timestamp"] = stamp.to_sec()
    return PointCloud2(header=Header(seq=seq, stamp=stamp, frame_id=frame_id), height=1,
                       width=len(points), fields=POINT_FIELDS, is_bigendian=False,
                       point_step=POINT_DTYPE.itemsize, row_step=POINT_DTYPE.itemsize * len(points),
                       data=points.tobytes(), is_dense=True)


def detections_message(detections, stamp, frame_id, seq):
    header = Header(seq=seq, stamp=stamp, frame_id=frame_id)
    message = Detection3DArray(header=header)
    for detection in detections:
        position = Point(*detection.position)
        orientation = Quaternion(*detection.quaternion)
        message.detections.append(Detection3D(
            header=header, id=detection.object_id, label=detection.label, score=1.0,
            bbox=BoundingBox3D(position=Pose(position, orientation),
                               size=Vector3(*detection.size)),
            velocity=Twist(linear=Vector3(detection.forward_speed, 0.0, 0.0),
                           angular=Vector3(0.0, 0.0, 0.0))))
    return message


def write_bag(drive, path, progress=None):
    """Write every message of `drive` to `path`; a partial bag never appears under that name."""
    config = drive.config
    counts = {"cloud": 0, "detections": 0}
    with written_atomically(path, "bag") as partial:
        with rosbag.Bag(partial, "w") as bag:
            events = drive.events()
            for done, (t, kind, index) in enumerate(events):
                stamp = ros_time(config.start_time, t)
                if kind == "cloud":
                    message = cloud_message(drive.cloud(index), stamp, config.lidar.frame_id,
                                            counts[kind])
                    topic = config.cloud_topic
                else:
                    message = detections_message(drive.detections(index), stamp,
                                                 config.lidar.frame_id, counts[kind])
                    topic = config.detections_topic
                bag.write(topic, message, stamp)
                counts[kind] += 1
                if progress is not None:
                    progress(done + 1, len(events), t)
    return counts
