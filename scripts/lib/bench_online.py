"""Behind scripts/bench_online: plays the test bag through launch/online.launch per method,
with the bag's boxes or the box-free path's (--boxes segment)."""
import argparse
import copy
import os
import subprocess
import sys
import tempfile
import time

import rosbag
import rosgraph
import rospy

from granular_tools.online.monitor import OnlineMonitor

REGISTRATION = ("icp", "icp_nl", "ndt")


def models_of(evaluation, method):
    if method in REGISTRATION:
        return os.path.join(evaluation, "train", "models")
    return os.path.join(evaluation, "classifiers", f"{method}.yml")


def crowded(bag, objects, folder):
    """A copy of `bag` in `folder` whose detection arrays repeat their boxes (new ids) until they
    hold at least `objects`: a frame as crowded as a busy real street, from the same clouds."""
    path = os.path.join(folder, f"crowded_{objects}.bag")
    with rosbag.Bag(bag) as reader, rosbag.Bag(path, "w") as writer:
        for topic, message, stamp in reader.read_messages():
            if message._type == "lgsvl_msgs/Detection3DArray" and message.detections:
                given = list(message.detections)
                copies = 0
                while len(message.detections) < objects:
                    copies += 1
                    for detection in given[:objects - len(message.detections)]:
                        repeated = copy.deepcopy(detection)
                        repeated.id = detection.id + 100000 * copies
                        message.detections.append(repeated)
            writer.write(topic, message, stamp)
    return path


def main():
    parser = argparse.ArgumentParser(prog="bench_online")
    # Given by scripts/bench_online, not by its user.
    parser.add_argument("--evaluation", required=True, help=argparse.SUPPRESS)
    parser.add_argument("--launch", required=True, help=argparse.SUPPRESS)
    parser.add_argument("--rate", type=float, default=10.0,
                        help="playback speed factor (default %(default)s); a method slower than "
                             "the frames come drops some (answered < frames)")
    parser.add_argument("--methods", default="svm,knn,icp,ndt")
    parser.add_argument("--track-vote", choices=("true", "false"), default="true",
                        help="online.launch's track_vote (default %(default)s)")
    parser.add_argument("--threads", type=int, default=None,
                        help="online.launch's threads:= (default: config/online.yaml's)")
    parser.add_argument("--preset", default=None,
                        help="online.launch's preset:= for the registration methods (default: "
                             "the launch file's, tuned)")
    parser.add_argument("--boxes", choices=("detections", "segment"), default="detections",
                        help="online.launch's boxes:= (default %(default)s); segment: the "
                             "box-free path's boxes (segment_cloud), whose time per cloud is "
                             "reported beside the classifier's")
    parser.add_argument("--track", choices=("true", "false"), default="true",
                        help="online.launch's track:= with --boxes segment (default %(default)s)")
    parser.add_argument("--objects", type=int, default=0,
                        help="repeat each frame's boxes until it holds at least N (a crowded "
                             "frame; the same clouds, so each copy costs what its box does)")
    args = parser.parse_args()
    segment = args.boxes == "segment"
    if segment and args.objects > 0:
        parser.error("--objects repeats the bag's boxes: not with --boxes segment")
    bag = os.path.join(args.evaluation, "..", "test.bag")
    scratch = tempfile.TemporaryDirectory()
    if args.objects > 0:
        bag = crowded(bag, args.objects, scratch.name)
    # The frames with detections (bag_to_files kept them): each should get an answer.
    pairs = len(os.listdir(os.path.join(args.evaluation, "test", "frames", "pcd")))
    with rosbag.Bag(bag) as reader:
        duration = reader.get_end_time() - reader.get_start_time()
    for _ in range(100):
        if rosgraph.is_master_online():
            break
        time.sleep(0.1)
    rospy.init_node("bench_online", anonymous=True)
    offered = pairs / duration * args.rate
    print(f"{os.path.basename(bag)}: {duration:.0f} s played at {args.rate:g}x: {pairs} frames "
          f"with detections, {offered:.0f} a second")
    if segment:
        # The frames the node answers are the clouds with a box, not known beforehand.
        print(f"boxes:=segment track:={args.track}: segment_cloud's time per cloud, the "
              "classifier's per frame, and the sum of their p95s (a bound on a frame's p95)")
        print(f"{'method':<8} {'clouds':>7} {'seg p95':>8} {'answered':>9} {'mean ms':>8} "
              f"{'p95 ms':>7} {'sum p95':>8} {'p95 / 0.1 s':>12}")
    else:
        print(f"{'method':<8} {'answered':>9} {'mean ms':>8} {'p95 ms':>7} {'frames/s':>9} "
              f"{'accuracy':>9} {'p95 / 0.1 s':>12}")
    for method in args.methods.split(","):
        monitor = OnlineMonitor()
        segmentation = OnlineMonitor(latency="/segmentation/latency_ms") if segment else None
        # svm_fitness registers every object against the models it learnt from.
        class_models = models_of(args.evaluation, "icp") if method == "svm_fitness" else ""
        subprocess.run(["roslaunch", args.launch, f"bag:={bag}", f"method:={method}",
                        f"models:={models_of(args.evaluation, method)}",
                        f"class_models:={class_models}", "rviz:=false",
                        f"rate:={args.rate}", f"track_vote:={args.track_vote}",
                        "exit_when_done:=true"]
                       + ([f"boxes:=segment", f"track:={args.track}"] if segment else [])
                       + ([f"threads:={args.threads}"] if args.threads is not None else [])
                       + ([f"preset:={args.preset}"] if args.preset is not None else []),
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(1.0)
        monitor.close()
        frames, mean, p95 = monitor.latency()
        if segment:
            segmentation.close()
            clouds, _, segment_p95 = segmentation.latency()
            print(f"{method:<8} {clouds:>7} {segment_p95:>8.2f} {frames:>9} {mean:>8.2f} "
                  f"{p95:>7.2f} {segment_p95 + p95:>8.2f} {(segment_p95 + p95) / 100:>12.3f}",
                  flush=True)
            continue
        correct, judged = monitor.accuracy()
        # frames/s: what the node can process, one frame after the other (1000 / mean ms).
        print(f"{method:<8} {frames:>4}/{pairs:<4} {mean:>8.2f} {p95:>7.2f} "
              f"{1000 / max(mean, 1e-9):>9.0f} {correct / max(judged, 1):>9.3f} "
              f"{p95 / 100:>12.3f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
