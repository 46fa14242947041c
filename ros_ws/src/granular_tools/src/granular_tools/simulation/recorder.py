"""A simulated drive written to a bag atomically, in the LGSVL simulator's layout."""
import rosbag

from ..messages import cloud_message, detections_message, ros_time
from ..output import written_atomically


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
                    returns = drive.cloud(index)
                    message = cloud_message(returns.points, returns.intensity, stamp,
                                            config.lidar.frame_id, counts[kind])
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
