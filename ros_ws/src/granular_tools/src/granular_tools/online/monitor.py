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
    """(x, y, yaw, length, width) of each detection's box."""
    boxes = []
    for detection in message.detections:
        pose, size = detection.bbox.position, detection.bbox.size
        q = pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        boxes.append((pose.position.x, pose.position.y, yaw, size.x, size.y))
    return boxes


class OnlineMonitor:
    """Subscribes to the classifier's output and latency, the ground truth and, when given,
    the segmentation's boxes; keeps everything for the summaries below."""

    def __init__(self, output="/classifier/output", latency="/classifier/latency_ms",
                 truth="/simulator/ground_truth/3d_detections", segments=None):
        self._lock = threading.Lock()
        self.outputs = []          # (cloud stamp ns, [(id, label, score)])
        self.latencies = []        # ms per frame
        self.true_labels = {}      # detection id -> label, from the ground truth
        self.truth = []            # (stamp ns, boxes)
        self.segments = []         # (stamp ns, boxes)
        self._subscribers = [
            rospy.Subscriber(output, Detection3DArray, self._on_output, queue_size=1000),
            rospy.Subscriber(latency, Float32, self._on_latency, queue_size=1000),
            rospy.Subscriber(truth, Detection3DArray, self._on_truth, queue_size=1000)]
        if segments:
            self._subscribers.append(
                rospy.Subscriber(segments, Detection3DArray, self._on_segments, queue_size=1000))

    def close(self):
        for subscriber in self._subscribers:
            subscriber.unregister()

    def _on_output(self, message):
        with self._lock:
            self.outputs.append((_nanoseconds(message.header),
                                 [(d.id, d.label, d.score) for d in message.detections]))

    def _on_latency(self, message):
        with self._lock:
            self.latencies.append(message.data)

    def _on_truth(self, message):
        with self._lock:
            for detection in message.detections:
                self.true_labels[detection.id] = detection.label
            self.truth.append((_nanoseconds(message.header), _boxes(message)))

    def _on_segments(self, message):
        with self._lock:
            self.segments.append((_nanoseconds(message.header), _boxes(message)))

    def labels(self):
        """Every label the classifier published."""
        with self._lock:
            return {label for _, detections in self.outputs for _, label, _ in detections}

    def accuracy(self):
        """(correct, classified) over the output detections whose true label is known (the
        ground truth's id) and that got a label other than 'unknown'."""
        with self._lock:
            pairs = [(label, self.true_labels.get(i)) for _, detections in self.outputs
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
        with self._lock:
            segments = sorted(self.segments)
            truth = list(self.truth)
        if not segments:
            return 0, 0
        stamps = np.array([stamp for stamp, _ in segments])
        found = total = 0
        for stamp, boxes in truth:
            nearest = int(np.argmin(np.abs(stamps - stamp)))
            if abs(stamps[nearest] - stamp) > slop_ns:
                continue
            centres = np.array([(x, y) for x, y, *_ in segments[nearest][1]]).reshape(-1, 2)
            for x, y, yaw, length, width in boxes:
                if math.hypot(x, y) > max_range:
                    continue
                total += 1
                offset = centres - (x, y)
                along = offset @ (math.cos(yaw), math.sin(yaw))
                across = offset @ (-math.sin(yaw), math.cos(yaw))
                found += bool(np.any((np.abs(along) <= length / 2) &
                                     (np.abs(across) <= width / 2)))
        return found, total
