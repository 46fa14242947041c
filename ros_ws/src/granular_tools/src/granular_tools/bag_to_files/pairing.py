"""The synchronisation policy of both modes: message_filters' ApproximateTimeSynchronizer.

The offline reader feeds the same synchroniser object as the live node's subscribers, so the
two modes pair the same messages when they see them in the same order.
"""
import dataclasses

import message_filters
import rospy

from .detections import DetectionCleaner


@dataclasses.dataclass
class PairingStats:
    clouds: int = 0
    detection_messages: int = 0
    pairs_kept: int = 0
    pairs_without_detections: int = 0
    clouds_written: int = 0  # clouds only: every cloud, with no detections file
    cleaning: str = ""  # what DetectionCleaner skipped or moved, when anything

    @property
    def clouds_unpaired(self):
        return self.clouds - self.pairs_kept - self.pairs_without_detections

    def summary(self, slop):
        if self.detection_messages == 0 and self.pairs_kept == 0 and self.clouds_written:
            return f"clouds read {self.clouds}, written {self.clouds_written} (clouds only)"
        return (f"clouds read {self.clouds}, detection messages {self.detection_messages}; "
                f"pairs kept {self.pairs_kept}; dropped: {self.clouds_unpaired} clouds with no "
                f"detection message within {slop * 1000:.0f} ms, "
                f"{self.pairs_without_detections} pairs with no detections"
                + (f"; {self.cleaning}" if self.cleaning else ""))


class Pairing:
    """Counts inputs and forwards each synchronised pair that has detections to `on_pair`."""

    def __init__(self, slop, queue_size, on_pair, load=None, cleaner=None):
        """`load` turns what was added into the message (for lazily read bag messages);
        `cleaner` (DetectionCleaner) keeps each pair's usable detections."""
        self.stats = PairingStats()
        self.on_pair = on_pair
        self.cleaner = cleaner or DetectionCleaner()
        self.load = load or (lambda message: message)
        self.cloud_input = message_filters.SimpleFilter()
        self.detections_input = message_filters.SimpleFilter()
        self.synchronizer = message_filters.ApproximateTimeSynchronizer(
            [self.cloud_input, self.detections_input], queue_size, slop)
        self.synchronizer.registerCallback(self._on_synchronised)

    def add_cloud(self, cloud):
        self.stats.clouds += 1
        self.cloud_input.signalMessage(cloud)

    def add_detections(self, detections):
        self.stats.detection_messages += 1
        self.detections_input.signalMessage(detections)

    def _on_synchronised(self, cloud, detections):
        detections = self.load(detections)
        if detections.detections:
            cloud = self.load(cloud)
            detections = self.cleaner.clean(cloud.header.frame_id, detections)
            self.stats.cleaning = self.cleaner.summary()
        if not detections.detections:
            self.stats.pairs_without_detections += 1
            return
        self.stats.pairs_kept += 1
        self.on_pair(cloud, detections)


class CloudsOnly:
    """The pairing of a bag without boxes: every cloud goes to `on_cloud` as it comes."""

    def __init__(self, on_cloud, load=None):
        self.stats = PairingStats()
        self.on_cloud = on_cloud
        self.load = load or (lambda message: message)

    def add_cloud(self, cloud):
        self.stats.clouds += 1
        self.on_cloud(self.load(cloud))
        self.stats.clouds_written += 1


def allow_without_node():
    """Let the synchroniser read rospy's wall clock without a node (it needs no roscore)."""
    rospy.rostime.set_rostime_initialized(True)
