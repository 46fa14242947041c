"""bag-to-files parameters, shared by the offline reader and the live node."""
import dataclasses


@dataclasses.dataclass(frozen=True)
class BagToFilesConfig:
    cloud_topic: str = "/simulator/lidar"
    detections_topic: str = "/simulator/ground_truth/3d_detections"
    slop: float = 0.01       # s, the most a cloud and a detection stamp may differ (report: 10 ms)
    queue_size: int = 10     # messages per topic the synchroniser keeps while waiting for a match
    # The bag has no boxes (a real sensor's): every cloud is written, with no detections file;
    # the box-free path (segmentation, cuboid fitting) makes the boxes.
    clouds_only: bool = False

    def check(self):
        if self.slop <= 0.0:
            raise ValueError(f"slop must be positive, got {self.slop}")
        if self.queue_size < 1:
            raise ValueError(f"queue_size must be at least 1, got {self.queue_size}")
        return self
