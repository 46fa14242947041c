"""bag-to-files parameters, shared by the offline reader and the live node."""
import dataclasses

from ..config_loading import bounded, check_fields


@dataclasses.dataclass(frozen=True)
class BagToFilesConfig:
    cloud_topic: str = "/simulator/lidar"
    detections_topic: str = "/simulator/ground_truth/3d_detections"
    # s, the most a cloud and a detection stamp may differ (report: 10 ms)
    slop: float = bounded(0.01, above=0.0, finite=True)
    # messages per topic the synchroniser keeps while waiting for a match
    queue_size: int = bounded(10, at_least=1)
    # The bag has no boxes (a real sensor's): every cloud is written, with no detections file;
    # the box-free path (segmentation, cuboid fitting) makes the boxes.
    clouds_only: bool = False

    def check(self):
        """The values given as options or node parameters (a file's are checked as loaded): a
        ConfigError (exit 2) naming the one out of range."""
        return check_fields(self)
