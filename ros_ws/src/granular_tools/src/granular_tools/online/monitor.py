"""OnlineMonitor: what the online classifier and the segmentation publish while a bag plays,
against the bag's ground truth; used by the online rostest and scripts/bench_online."""
import math
import threading

import numpy as np
import rospy
from lgsvl_msgs.msg import Detection3DArray
from std_msgs.msg import Float32

from ..labels import UNKNOWN


def _nanoseconds(header):
    return header.stamp.to_nsec()


def _boxes(message):
    """(x, y, yaw, length, width, id) of each detection's box."""
    boxes = []
    for detection in message.detections:
        pose, size = detection.bbox.position, detection.bbox.size
        q = pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        boxes.append((pose.position.x, pose.position.y, yaw, size.x, size.y, detection.id))
    return boxes


def _inside(centres, x, y, yaw, length, width):
    """Which of `centres` (n x 2) lie in the footprint of the box (x, y, yaw, length, width)."""
    offset = centres - (x, y)
    along = offset @ (math.cos(yaw), math.sin(yaw))
    across = offset @ (-math.sin(yaw), math.cos(yaw))
    return (np.abs(along) <= length / 2) & (np.abs(across) <= width / 2)


class OnlineMonitor:
    """Subscribes to the classifier's output and latency, the ground truth and, when given,
    the segmentation's boxes; keeps everything for the summaries below.

    The detection arrays are kept as they arrive, serialised, and decoded when a summary (or
    `outputs`, `truth`, `true_labels`, `segments`) asks: decoding a crowded frame's 200 boxes,
    twice a frame, took the monitor about a fifth of a core while the bag played, on the same
    cores as the node whose latency it measures."""

    def __init__(self, output="/classifier/output", latency="/classifier/latency_ms",
                 truth="/simulator/ground_truth/3d_detections", segments=None):
        self._lock = threading.Lock()
        self._received = []        # (kind, serialised Detection3DArray), in arrival order
        self._outputs = []         # (cloud stamp ns, [(id, label, score)])
        self.latencies = []        # ms per frame
        self._true_labels = {}     # detection id -> label, from the ground truth
        self._truth = []           # (stamp ns, boxes)
        self._segments = []        # (stamp ns, boxes)
        self._subscribers = [
            rospy.Subscriber(output, rospy.AnyMsg, self._keep, "output", queue_size=1000),
            rospy.Subscriber(latency, Float32, self._on_latency, queue_size=1000),
            rospy.Subscriber(truth, rospy.AnyMsg, self._keep, "truth", queue_size=1000)]
        if segments:
            self._subscribers.append(
                rospy.Subscriber(segments, rospy.AnyMsg, self._keep, "segments",
                                 queue_size=1000))

    def close(self):
        for subscriber in self._subscribers:
            subscriber.unregister()

    def _keep(self, message, kind):
        with self._lock:
            self._received.append((kind, message._buff))

    def _on_latency(self, message):
        with self._lock:
            self.latencies.append(message.data)

    def _decode(self):
        """Decodes what arrived since the last call; call with the lock held."""
        for kind, serialised in self._received:
            message = Detection3DArray().deserialize(serialised)
            if kind == "output":
                self._outputs.append((_nanoseconds(message.header),
                                      [(d.id, d.label, d.score) for d in message.detections]))
            elif kind == "truth":
                for detection in message.detections:
                    self._true_labels[detection.id] = detection.label
                self._truth.append((_nanoseconds(message.header), _boxes(message)))
            else:
                self._segments.append((_nanoseconds(message.header), _boxes(message)))
        self._received.clear()

    def _copy(self, decoded):
        """A copy of `decoded` (a list or dict above) once everything received is decoded."""
        with self._lock:
            self._decode()
            return decoded.copy()

    @property
    def outputs(self):
        """(cloud stamp ns, [(id, label, score)]) of each output message."""
        return self._copy(self._outputs)

    @property
    def truth(self):
        """(stamp ns, boxes) of each ground-truth message."""
        return self._copy(self._truth)

    @property
    def true_labels(self):
        """Detection id -> label, from the ground truth."""
        return self._copy(self._true_labels)

    @property
    def segments(self):
        """(stamp ns, boxes) of each segmentation message."""
        return self._copy(self._segments)

    def labels(self):
        """Every label the classifier published."""
        return {label for _, detections in self.outputs for _, label, _ in detections}

    def accuracy(self):
        """(correct, classified) over the output detections whose true label is known (the
        ground truth's id) and that got a label other than 'unknown'."""
        true_labels = self.true_labels
        pairs = [(label, true_labels.get(i)) for _, detections in self.outputs
                 for i, label, _ in detections]
        judged = [(label, truth) for label, truth in pairs if truth and label != UNKNOWN]
        return sum(label == truth for label, truth in judged), len(judged)

    def latency(self):
        """(frames, mean ms, p95 ms)."""
        with self._lock:
            values = np.array(self.latencies)
        if values.size == 0:
            return 0, 0.0, 0.0
        return values.size, float(values.mean()), float(np.percentile(values, 95))

    def segmentation_recall(self, max_range=25.0, slop_ns=10_000_000):
        """(found, true objects) over the true boxes within `max_range` m of the sensor in the
        ground-truth messages that have a segmentation message within `slop_ns`: a true object
        is found when a segment's box centre lies in its footprint."""
        segments = sorted(self.segments)
        truth = self.truth
        if not segments:
            return 0, 0
        stamps = np.array([stamp for stamp, _ in segments])
        found = total = 0
        for stamp, boxes in truth:
            nearest = int(np.argmin(np.abs(stamps - stamp)))
            if abs(stamps[nearest] - stamp) > slop_ns:
                continue
            centres = np.array([(x, y) for x, y, *_ in segments[nearest][1]]).reshape(-1, 2)
            for x, y, yaw, length, width, _ in boxes:
                if math.hypot(x, y) > max_range:
                    continue
                total += 1
                found += bool(np.any(_inside(centres, x, y, yaw, length, width)))
        return found, total

    def segment_ids(self, max_range=25.0, slop_ns=10_000_000):
        """True vehicle id -> the ids of the segments found in its footprint (see
        segmentation_recall), one list per frame with a segmentation message, in stamp order:
        with tracking, a vehicle followed well keeps one id."""
        segments = sorted(self.segments)
        if not segments:
            return {}
        stamps = np.array([stamp for stamp, _ in segments])
        followed = {}
        for stamp, boxes in sorted(self.truth):
            nearest = int(np.argmin(np.abs(stamps - stamp)))
            if abs(stamps[nearest] - stamp) > slop_ns:
                continue
            found = segments[nearest][1]
            centres = np.array([(x, y) for x, y, *_ in found]).reshape(-1, 2)
            for x, y, yaw, length, width, vehicle in boxes:
                if math.hypot(x, y) > max_range:
                    continue
                inside = _inside(centres, x, y, yaw, length, width)
                followed.setdefault(vehicle, []).append(
                    [found[i][5] for i in np.flatnonzero(inside)])
        return followed
