"""summarize_bag: what a LiDAR + 3D-detection bag holds, per topic and per class."""
import argparse
import bisect
import collections
import sys

import numpy as np

THRESHOLDS = (10, 50, 100, 300, 500)  # the report's N_thresh test sets


def summarize(path, cloud_topic, detections_topic, slop, out=sys.stdout):
    # Imported here so that --help works without ROS on the path.
    from .bags import open_bag
    from .geometry import count_points_inside
    from .messages import cloud_xyz, detection_cuboid

    with open_bag(path) as bag:
        info = bag.get_type_and_topic_info()
        print(f"{path}: {bag.get_end_time() - bag.get_start_time():.1f} s, "
              f"{bag.get_message_count()} messages", file=out)
        for topic, topic_info in sorted(info.topics.items()):
            rate = f", {topic_info.frequency:.1f} Hz" if topic_info.frequency else ""
            print(f"  {topic}: {topic_info.message_count} x {topic_info.msg_type}{rate}", file=out)
        for topic in (cloud_topic, detections_topic):
            if topic not in info.topics:
                raise ValueError(f"{path} has no topic {topic} (it has: "
                                 f"{', '.join(sorted(info.topics))})")
        detection_stamps, detection_messages = [], []
        for _, message, _ in bag.read_messages(topics=[detections_topic]):
            detection_stamps.append(message.header.stamp.to_sec())
            detection_messages.append(message)
        order = np.argsort(detection_stamps)
        detection_stamps = [detection_stamps[i] for i in order]
        detection_messages = [detection_messages[i] for i in order]

        objects = collections.defaultdict(set)
        for message in detection_messages:
            for detection in message.detections:
                objects[detection.label].add(detection.id)

        points_per_cloud, paired, frame_ids = [], 0, set()
        box_points = collections.defaultdict(list)
        for _, cloud, _ in bag.read_messages(topics=[cloud_topic]):
            frame_ids.add(cloud.header.frame_id)
            xyz = cloud_xyz(cloud)
            points_per_cloud.append(len(xyz))
            stamp = cloud.header.stamp.to_sec()
            nearest = _nearest(detection_stamps, stamp)
            if nearest is None or abs(detection_stamps[nearest] - stamp) > slop:
                continue
            paired += 1
            for detection in detection_messages[nearest].detections:
                box_points[detection.label].append(
                    count_points_inside(xyz, detection_cuboid(detection)))

    counts = np.array(points_per_cloud)
    print(f"clouds: {len(counts)}, frame {', '.join(sorted(frame_ids))}, points per cloud "
          f"min {counts.min()} mean {counts.mean():.0f} max {counts.max()}", file=out)
    print(f"clouds with a detection message within {slop * 1000:.0f} ms: {paired} "
          f"({100.0 * paired / max(len(counts), 1):.0f}%)", file=out)
    print("objects per class (distinct ids) and boxes in the paired frames with at least N "
          "points:", file=out)
    header = f"  {'class':<12}{'objects':>8}" + "".join(f"{f'>={n}':>8}" for n in THRESHOLDS)
    print(header, file=out)
    for label in sorted(objects):
        points = np.array(box_points.get(label, []), dtype=int)
        row = f"  {label:<12}{len(objects[label]):>8}"
        row += "".join(f"{int(np.count_nonzero(points >= n)):>8}" for n in THRESHOLDS)
        print(row, file=out)


def _nearest(sorted_stamps, stamp):
    if not sorted_stamps:
        return None
    i = bisect.bisect_left(sorted_stamps, stamp)
    candidates = [j for j in (i - 1, i) if 0 <= j < len(sorted_stamps)]
    return min(candidates, key=lambda j: abs(sorted_stamps[j] - stamp))


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="summarize_bag",
        description="Print what a bag of LiDAR clouds and lgsvl_msgs 3D detections holds: topics, "
                    "points per cloud, how many clouds have a detection message within the slop, "
                    "objects per class and how many of their boxes hold at least 10/50/100/300/500 "
                    "points.")
    parser.add_argument("bag")
    parser.add_argument("--cloud-topic", default="/simulator/lidar",
                        help="sensor_msgs/PointCloud2 topic (default %(default)s)")
    parser.add_argument("--detections-topic", default="/simulator/ground_truth/3d_detections",
                        help="lgsvl_msgs/Detection3DArray topic (default %(default)s)")
    parser.add_argument("--slop", type=float, default=0.01, metavar="SECONDS",
                        help="pairing tolerance between stamps (default: %(default)s)")
    args = parser.parse_args(argv)
    try:
        summarize(args.bag, args.cloud_topic, args.detections_topic, args.slop)
    except Exception as error:  # rosbag raises its own types for unreadable files.
        print(f"summarize_bag: error: {error}", file=sys.stderr)
        return 1
    return 0
