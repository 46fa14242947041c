"""bag_to_files: the offline mode, reading a bag directly (no roscore), deterministically."""
import argparse
import dataclasses
import struct
import time

import genpy
from std_msgs.msg import Header

from .. import progress
from ..bags import READ_ERRORS, BagError, open_bag
from ..config_loading import ConfigError, load_yaml_over
from ..output import OutputError, OutputFolder, run_main
from ..pcd import CloudError
from .config import BagToFilesConfig
from .detections import DetectionCleaner, bag_transforms
from .pairing import CloudsOnly, Pairing, allow_without_node
from .writer import PairWriter, prepare_output


class StampedRaw:
    """A bag message read raw: its header is decoded, the rest only when `load`ed.

    Clouds and detection arrays both begin with std_msgs/Header (seq, secs, nsecs), which is
    all the synchroniser looks at; most messages are never paired and never fully decoded.
    """
    __slots__ = ("header", "raw", "message_class")

    def __init__(self, raw, message_class):
        seq, secs, nsecs = struct.unpack_from("<3I", raw)
        self.header = Header(seq=seq, stamp=genpy.Time(secs, nsecs))
        self.raw, self.message_class = raw, message_class

    def load(self):
        return self.message_class().deserialize(self.raw)


def read_topics(config):
    """The topics a conversion reads, with the message type each must carry."""
    topics = {config.cloud_topic: "sensor_msgs/PointCloud2"}
    if not config.clouds_only:
        topics[config.detections_topic] = "lgsvl_msgs/Detection3DArray"
    return topics


def check_topics(bag, path, config):
    """The messages to read; a BagError naming what the bag holds when a topic is missing."""
    topics = bag.get_type_and_topic_info().topics
    expected = read_topics(config)
    for topic, message_type in expected.items():
        if topic not in topics:
            held = ", ".join(f"{t} ({i.msg_type})" for t, i in sorted(topics.items())) or "none"
            advice = ("" if config.clouds_only or topic != config.detections_topic else
                      "; for a bag without boxes use --clouds-only")
            raise BagError(f"{path}: no topic {topic}; the bag has: {held}{advice}")
        if topics[topic].msg_type != message_type:
            raise BagError(f"{path}: {topic} carries {topics[topic].msg_type}, "
                           f"expected {message_type}")
    return sum(topics[topic].message_count for topic in expected)


def has_detections(bag_path, config):
    """Whether the bag at `bag_path` carries config.detections_topic (else: a clouds-only bag)."""
    with open_bag(bag_path) as bag:
        return config.detections_topic in bag.get_type_and_topic_info().topics


def convert(bag_path, folder, config, reporter=None):
    """Write every kept pair of `bag_path` into `folder` (which must be ready); return stats."""
    allow_without_node()
    writer = PairWriter(folder, staged=True)
    bag = open_bag(bag_path)
    with bag:
        total = check_topics(bag, bag_path, config)
        if config.clouds_only:
            pairing = CloudsOnly(writer.write_cloud, load=StampedRaw.load)
        else:
            try:
                cleaner = DetectionCleaner(bag_transforms(bag, bag_path))
            except READ_ERRORS as error:
                raise BagError(f"{bag_path}: cannot read its /tf: {error}") from error
            pairing = Pairing(config.slop, config.queue_size, writer.write,
                              load=StampedRaw.load, cleaner=cleaner)
        done = 0
        try:
            # Messages in the order they were recorded, as `rosbag play` would publish them.
            for topic, (_, raw, _, _, message_class), _ in bag.read_messages(
                    topics=list(read_topics(config)), raw=True):
                message = StampedRaw(raw, message_class)
                if topic == config.cloud_topic:
                    pairing.add_cloud(message)
                else:
                    pairing.add_detections(message)
                done += 1
                if reporter is not None:
                    reporter(done, total)
        except READ_ERRORS as error:
            raise BagError(f"{bag_path}: corrupt or truncated after {done} of {total} messages: "
                           f"{error}") from error
    return pairing.stats


def convert_into_new_folder(bag_path, out, config, overwrite, reporter=None):
    """Convert into a staging sibling of `out`, put in place only when complete (OutputFolder:
    locked, never replacing a folder that no granular tool wrote)."""
    with OutputFolder(out, "bag_to_files", overwrite, inputs=(bag_path,)) as folder:
        prepare_output(folder.staging)
        stats = convert(bag_path, folder.staging, config, reporter)
        folder.commit()
    return stats


def main(argv=None):
    defaults = BagToFilesConfig()
    parser = argparse.ArgumentParser(
        prog="bag_to_files",
        description="Synchronise LiDAR clouds with lgsvl_msgs 3D detections straight from a bag "
                    "(message_filters.ApproximateTimeSynchronizer, as the live node) and write "
                    "OUT/pcd/<stamp>.pcd and OUT/detections_3d/<stamp>.json for every pair with "
                    "at least one detection; with --clouds-only (a bag without boxes) every "
                    "cloud, and no detections files. Needs no roscore; the same bag gives the "
                    "same files.")
    parser.add_argument("--bag", required=True, help="bag to read")
    parser.add_argument("--out", required=True, help="output folder (created; must not hold "
                                                     "results unless --overwrite)")
    parser.add_argument("--config", metavar="FILE.yaml",
                        help="parameters laid over the defaults (see config/bag_to_files.yaml)")
    parser.add_argument("--cloud-topic", help=f"default: {defaults.cloud_topic}")
    parser.add_argument("--detections-topic", help=f"default: {defaults.detections_topic}")
    parser.add_argument("--slop", type=float, metavar="SECONDS",
                        help=f"most a pair's stamps may differ (default: {defaults.slop})")
    parser.add_argument("--clouds-only", action="store_true", default=None,
                        help="the bag has no boxes: write every cloud as pcd/<stamp>.pcd and "
                             "no detections_3d/ files (the box-free path makes the boxes)")
    parser.add_argument("--queue-size", type=int,
                        help=f"synchroniser queue per topic (default: {defaults.queue_size})")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace an output folder that already holds results")
    parser.add_argument("--quiet", action="store_true", help="no progress or summary")
    args = parser.parse_args(argv)

    def run():
        config = load_yaml_over(defaults, args.config) if args.config else defaults
        overrides = {key: value for key, value in (
            ("cloud_topic", args.cloud_topic), ("detections_topic", args.detections_topic),
            ("slop", args.slop), ("queue_size", args.queue_size),
            ("clouds_only", args.clouds_only)) if value is not None}
        config = dataclasses.replace(config, **overrides).check()
        reporter = None if args.quiet else progress.Reporter("bag to files", unit="messages")
        started = time.monotonic()
        stats = convert_into_new_folder(args.bag, args.out, config, args.overwrite, reporter)
        if not args.quiet:
            reporter.finish()
            print(f"bag_to_files: {args.out}: {stats.summary(config.slop)} "
                  f"({time.monotonic() - started:.1f} s)")
        return 0

    return run_main("bag_to_files", run, (ConfigError, BagError, CloudError, OutputError,
                                          ValueError))
