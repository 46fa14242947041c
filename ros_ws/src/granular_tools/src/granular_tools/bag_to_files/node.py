"""bag_to_files_node: the live mode, subscribing to a cloud and a detections topic."""
import threading

import rospy
import tf2_ros
from lgsvl_msgs.msg import Detection3DArray
from sensor_msgs.msg import PointCloud2

from ..nodes import init_node
from ..output import OutputError, claimed_folder
from ..pcd import CloudError
from .config import BagToFilesConfig
from .detections import DetectionCleaner
from .pairing import CloudsOnly, Pairing
from .writer import PairWriter, prepare_output

SILENCE_WARNING_AFTER = 5.0  # s without a message on a topic before a warning
TF_WAIT = 0.05  # s a detection waits for its frame's transform before it is skipped


def read_config():
    defaults = BagToFilesConfig()
    return BagToFilesConfig(
        cloud_topic=rospy.get_param("~cloud_topic", defaults.cloud_topic),
        detections_topic=rospy.get_param("~detections_topic", defaults.detections_topic),
        slop=float(rospy.get_param("~slop", defaults.slop)),
        queue_size=int(rospy.get_param("~queue_size", defaults.queue_size)),
        clouds_only=bool(rospy.get_param("~clouds_only", defaults.clouds_only))).check()


class BagToFilesNode:
    def __init__(self, out, config):
        self.out, self.config = out, config
        prepare_output(self.out)
        writer = PairWriter(self.out)
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self._writer = writer
        # Both subscriber threads feed one synchroniser; one lock keeps the counts exact.
        self.lock = threading.Lock()
        self.failed = None
        rospy.Subscriber(self.config.cloud_topic, PointCloud2, self._on_cloud, queue_size=50)
        if self.config.clouds_only:
            self.pairing = CloudsOnly(self._write_cloud)
            rospy.loginfo("bag_to_files: writing every cloud of %s (clouds only) into %s",
                          self.config.cloud_topic, self.out)
        else:
            self.pairing = Pairing(self.config.slop, self.config.queue_size, self._write,
                                   cleaner=DetectionCleaner(self._lookup))
            rospy.Subscriber(self.config.detections_topic, Detection3DArray,
                             self._on_detections, queue_size=100)
            rospy.loginfo("bag_to_files: writing pairs of %s and %s (slop %.3f s) into %s",
                          self.config.cloud_topic, self.config.detections_topic,
                          self.config.slop, self.out)
        rospy.Timer(rospy.Duration(SILENCE_WARNING_AFTER), self._warn_if_silent, oneshot=True)

    def _lookup(self, target, source, stamp):
        try:
            return self.tf_buffer.lookup_transform(target, source, stamp,
                                                   rospy.Duration(TF_WAIT)).transform
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException):
            rospy.logwarn_throttle(10.0, f"bag_to_files: no transform from {source} to {target}; "
                                         "its detections are skipped")
            return None

    def _write(self, cloud, detections):
        try:
            self._writer.write(cloud, detections)
        except (CloudError, OSError) as error:
            self.failed = error
            rospy.signal_shutdown(f"cannot write a pair: {error}")

    def _write_cloud(self, cloud):
        try:
            self._writer.write_cloud(cloud)
        except (CloudError, OSError) as error:
            self.failed = error
            rospy.signal_shutdown(f"cannot write a cloud: {error}")

    def _on_cloud(self, cloud):
        with self.lock:
            self.pairing.add_cloud(cloud)

    def _on_detections(self, detections):
        with self.lock:
            self.pairing.add_detections(detections)

    def _warn_if_silent(self, _event):
        stats = self.pairing.stats
        watched = [(self.config.cloud_topic, stats.clouds)]
        if not self.config.clouds_only:
            watched.append((self.config.detections_topic, stats.detection_messages))
        for topic, count in watched:
            if count == 0:
                rospy.logwarn("bag_to_files: nothing on %s after %.0f s; still waiting", topic,
                              SILENCE_WARNING_AFTER)

    def summary(self):
        return self.pairing.stats.summary(self.config.slop)


def main(description):
    """The node; `description` is its script's help."""
    init_node("bag_to_files", description)
    try:
        out, config = rospy.get_param("~out"), read_config()
        overwrite = bool(rospy.get_param("~overwrite", False))
        with claimed_folder(out, "bag_to_files_node", overwrite, hint="_overwrite:=true"):
            node = BagToFilesNode(out, config)
            rospy.spin()
    except KeyError as error:
        rospy.logfatal("bag_to_files: missing parameter %s", error)
        return 1
    except (ValueError, OutputError) as error:
        rospy.logfatal("bag_to_files: %s", error)
        return 1
    rospy.loginfo("bag_to_files: %s", node.summary())
    return 1 if node.failed else 0
