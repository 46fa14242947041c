"""What a pair keeps of its detections: boxes whose numbers are all finite (JSON has no NaN),
in the cloud's frame. A detection in another frame is moved into the cloud's with the bag's
/tf and /tf_static (offline) or tf2's listener (live); without a transform it is skipped. Each
skip is counted, by reason, for the run's summary."""
import collections
import math

import numpy as np
from geometry_msgs.msg import Point, Pose, Quaternion
from lgsvl_msgs.msg import Detection3DArray

from ..geometry import quaternion_multiply, rotate


def _finite(detection):
    pose, size = detection.bbox.position, detection.bbox.size
    numbers = (pose.position.x, pose.position.y, pose.position.z, pose.orientation.x,
               pose.orientation.y, pose.orientation.z, pose.orientation.w, size.x, size.y,
               size.z)
    return all(math.isfinite(n) for n in numbers)


def transform_pose(transform, pose):
    """`pose` moved by a geometry_msgs/Transform (the child frame's pose into the parent's)."""
    r = transform.rotation
    q = (r.x, r.y, r.z, r.w)
    p = pose.position
    moved = rotate(q, (p.x, p.y, p.z)) + np.array([transform.translation.x,
                                                     transform.translation.y,
                                                     transform.translation.z])
    o = pose.orientation
    x, y, z, w = quaternion_multiply(q, (o.x, o.y, o.z, o.w))
    return Pose(Point(*moved), Quaternion(x, y, z, w))


NON_FINITE = "a box with NaN or infinite numbers"
NON_FINITE_NAMED = 5  # boxes named in the summary; the count covers them all


class DetectionCleaner:
    """Cleans each pair's detections; `lookup(target, source, stamp)` gives the
    geometry_msgs/Transform from `source` into `target`, or None when there is none."""

    def __init__(self, lookup=None):
        self.lookup = lookup or (lambda target, source, stamp: None)
        self.skipped = collections.Counter()  # reason -> detections
        self.non_finite = []  # the first NON_FINITE_NAMED boxes with NaN or infinite numbers
        self.transformed = 0

    def clean(self, cloud_frame, message):
        kept = Detection3DArray(header=message.header)
        kept.header.frame_id = cloud_frame
        for detection in message.detections:
            if not _finite(detection):
                self.skipped[NON_FINITE] += 1
                if len(self.non_finite) < NON_FINITE_NAMED:
                    stamp = message.header.stamp
                    self.non_finite.append(f"id {detection.id} '{detection.label}' in frame "
                                           f"{stamp.secs}.{stamp.nsecs:09d}")
                continue
            frame = detection.header.frame_id or message.header.frame_id or cloud_frame
            if frame != cloud_frame:
                stamp = message.header.stamp if detection.header.stamp.is_zero() \
                    else detection.header.stamp
                transform = self.lookup(cloud_frame, frame, stamp)
                if transform is None:
                    self.skipped[f"in frame '{frame}' with no transform to the cloud's "
                                 f"'{cloud_frame}'"] += 1
                    continue
                detection.bbox.position = transform_pose(transform, detection.bbox.position)
                self.transformed += 1
            detection.header.frame_id = cloud_frame
            kept.detections.append(detection)
        return kept

    def summary(self):
        parts = [f"{count} {reason}" + (f" ({', '.join(self.non_finite)}"
                                        f"{', ...' if count > len(self.non_finite) else ''})"
                                        if reason == NON_FINITE else "")
                 for reason, count in sorted(self.skipped.items())]
        text = f"detections skipped: {', '.join(parts)}" if parts else ""
        if self.transformed:
            text += ("; " if text else "") + \
                f"{self.transformed} detections moved into the cloud's frame with tf"
        return text


def bag_transforms(bag, bag_path):
    """A lookup over the bag's /tf and /tf_static, or None when it has neither."""
    import rospy
    import tf2_py

    topics = bag.get_type_and_topic_info().topics
    tf_topics = [t for t in ("/tf", "/tf_static") if t in topics]
    if not tf_topics:
        return None
    span = max(bag.get_end_time() - bag.get_start_time(), 0.0) + 10.0
    buffer = tf2_py.BufferCore(rospy.Duration.from_sec(span))
    for topic, message, _ in bag.read_messages(topics=tf_topics):
        for transform in message.transforms:
            if topic == "/tf_static":
                buffer.set_transform_static(transform, bag_path)
            else:
                buffer.set_transform(transform, bag_path)

    def lookup(target, source, stamp):
        try:
            return buffer.lookup_transform_core(target, source, stamp).transform
        except tf2_py.TransformException:
            return None

    return lookup
