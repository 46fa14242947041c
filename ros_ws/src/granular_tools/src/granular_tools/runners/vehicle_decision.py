"""train_vehicle_decision: the few-shot vehicle decision, tuned on a user's labelled frames.

The zero-shot decision (config/cuboids.yaml `evidence:`, docs/cuboids.md) judges each fitted
segment from cues that hold for every LiDAR. Given a few frames whose boxes a user labelled
(label_cuboids, or KITTI's label_2 through kitti_to_bag and bag_to_files), this tool adjusts
its thresholds to that sensor and site: coordinate descent over max_pass_share, min_fill,
max_face_distance, min_points (with min_body_points), min_top, max_car_length, min_long_top,
tall_clear_share and min_across_sight, two passes over a few values each (at most 60 fits),
each candidate scored by fitting the frames' segments (fit_cuboids --boxes segment) and
matching the cuboids to the labelled vehicles (evaluate_cuboids' paper criterion: centre
within 0.5 m, yaw within 10 degrees). A change is kept only when it raises F1 over the frames: with no better
candidate the zero-shot values stay, so a few frames cannot talk the decision into anything
they do not show. The file written holds the `evidence:` keys, and cuboids.launch and
online.launch take it as `classifier:=` (fit_cuboids --classifier), laid over their
config/cuboids.yaml.
"""
import argparse
import os
import shutil
import subprocess
import tempfile

import yaml

from .. import progress
from ..config_loading import ConfigError
from ..evaluation.cuboid_matching import DEFAULT_CLASS_MAP, Filters, Settings, evaluate
from ..output import OutputError, resolve, run_main, write_file
from .stages import (StageError, add_sensor_options, bad_argument,
                     existing_file, positive_number, sensor_arguments, sensor_option,
                     without_rosrun)

TOOL = "train_vehicle_decision"

# The evidence keys tuned and the values tried for each (config/cuboids.yaml says what each
# does). min_points stands for the pair min_points / min_body_points, scaled together.
TUNED = {
    "max_pass_share": (0.1, 0.15, 0.2, 0.3),
    "min_fill": (0.7, 0.8, 0.85, 0.9),
    "max_face_distance": (0.25, 0.35, 0.5),
    "min_points": (0.5, 1.0, 1.5, 2.0),
    "min_top": (0.6, 0.8, 1.0),
    "max_car_length": (5.0, 5.5, 6.5),
    "min_long_top": (2.2, 2.6, 3.0),
    "tall_clear_share": (0.3, 0.5, 0.7),
    "min_across_sight": (1.2, 1.5, 1.6),
}
SWEEPS = 2  # passes over TUNED; a pass that changes nothing ends the search


def parser():
    p = argparse.ArgumentParser(
        prog=TOOL, description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--frames", required=True, nargs="+", metavar="FOLDER",
                   help="frames folders (bag to files' layout) whose detections_3d/ hold the "
                        "labelled boxes")
    p.add_argument("--out", required=True, metavar="FILE.yaml",
                   help="the vehicle decision to write (refused if it exists, unless "
                        "--overwrite)")
    p.add_argument("--labels", required=True, metavar="LIST",
                   help="the labels that are vehicles, comma-separated (KITTI: Car or "
                        "Car,Van,Truck; the simulator: Sedan,SUV,Hatchback,Jeep,BoxTruck,"
                        "SchoolBus); every other box is neither sought nor counted against")
    p.add_argument("--config", metavar="FILE",
                   help="cuboids config to start from (default: fit_cuboids' built-in, as "
                        "config/cuboids.yaml)")
    p.add_argument("--max-range", type=float, default=50.0, metavar="M",
                   help="vehicles within this range are sought (default %(default)s)")
    p.add_argument("--min-points", type=int, default=50, metavar="N",
                   help="vehicles with at least this many points are sought (default "
                        "%(default)s)")
    p.add_argument("--field-of-view", type=float, metavar="DEG",
                   help="only boxes within DEG either side of straight ahead (labels made in a "
                        "camera's view, as KITTI's: 40)")
    add_sensor_options(p)
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    p.add_argument("--quiet", action="store_true", help="no progress")
    return p


class Tuning:
    """Scores evidence settings on the labelled frames, each in a scratch folder."""

    def __init__(self, args, scratch):
        self.args, self.scratch, self.runs = args, scratch, 0
        self.filters = Filters(args.max_range, args.min_points,
                               tuple(args.labels.split(",")), args.field_of_view)
        base = {}
        if args.config:
            with open(args.config, encoding="utf-8") as stream:
                base = yaml.safe_load(stream) or {}
            if not isinstance(base, dict):
                raise ConfigError(f"{args.config}: not a cuboids config (no mapping)")
        self.base = base
        self.base_points = {key: (base.get("evidence") or {}).get(key, default)
                            for key, default in (("min_points", 30), ("min_body_points", 20))}

    def evidence(self, settings):
        """The `evidence:` keys for `settings` (min_points scales both point counts)."""
        keys = {key: value for key, value in settings.items() if key != "min_points"}
        if "min_points" in settings:
            for key, base in self.base_points.items():
                keys[key] = max(1, round(base * settings["min_points"]))
        return keys

    def score(self, settings):
        """(F1, TP, FP, FN) of the paper's criterion over every frames folder."""
        config = dict(self.base)
        config["evidence"] = {**(config.get("evidence") or {}), **self.evidence(settings)}
        self.runs += 1
        run = os.path.join(self.scratch, str(self.runs))
        os.makedirs(run)
        config_file = os.path.join(run, "cuboids.yaml")
        with open(config_file, "w", encoding="utf-8") as stream:
            yaml.safe_dump(config, stream)
        tp = fp = fn = 0
        for index, frames in enumerate(self.args.frames):
            fitted = os.path.join(run, f"cuboids{index}")
            command = ["rosrun", "granular_ros", "fit_cuboids", "--frames", frames, "--out",
                       fitted, "--boxes", "segment", "--config", config_file]
            command += sensor_arguments(self.args)
            fit = subprocess.run(without_rosrun(command), capture_output=True, text=True,
                                 check=False)
            if fit.returncode != 0:
                raise StageError("fit_cuboids", fit.stderr.strip() or
                                 f"failed with exit status {fit.returncode}", fit.returncode)
            summary, _ = evaluate(Settings(frames, fitted, DEFAULT_CLASS_MAP, self.filters),
                                  None)
            paper = summary["overall"]["criteria"]["paper"]
            tp, fp, fn = tp + paper["tp"], fp + paper["fp"], fn + paper["fn"]
        shutil.rmtree(run)
        f1 = 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else 0.0
        return f1, tp, fp, fn


def tune(tuning, reporter, total):
    """Coordinate descent from the zero-shot values (settings {} are the config's)."""
    chosen = {}
    best = start = tuning.score(chosen)
    for _ in range(SWEEPS):
        changed = False
        for key, values in TUNED.items():
            for value in values:
                if chosen.get(key) == value:
                    continue
                trial = tuning.score({**chosen, key: value})
                if reporter:
                    reporter(tuning.runs - 1, total)
                if trial[0] > best[0] + 1e-9:
                    best, chosen, changed = trial, {**chosen, key: value}, True
        if not changed:
            break
    return start, best, chosen


def written(args, start, best, chosen, evidence):
    frames = ", ".join(args.frames)
    lines = [f"# Vehicle decision by {TOOL}: take it as cuboids.launch or online.launch",
             "# classifier:= (fit_cuboids --classifier); its keys go over config/cuboids.yaml.",
             f"# Tuned on {frames}: vehicles {args.labels}, at least {args.min_points} points,",
             f"# within {args.max_range:g} m" + (f", {args.field_of_view:g} deg either side"
                                                 if args.field_of_view else "") + ".",
             f"# F1 (centre within 0.5 m, yaw within 10 deg): zero-shot {start[0]:.3f} "
             f"(TP {start[1]}, FP {start[2]}, FN {start[3]}), tuned {best[0]:.3f} "
             f"(TP {best[1]}, FP {best[2]}, FN {best[3]})."]
    if not evidence:
        lines.append("# No key: no change measured better than the zero-shot values.")
    body = yaml.safe_dump({"evidence": evidence}, default_flow_style=False) if evidence \
        else "evidence: {}\n"
    return "\n".join(lines) + "\n" + body


def main(argv=None):
    args = parser().parse_args(argv)

    def body():
        args.out = resolve(args.out)
        if os.path.exists(args.out) and not args.overwrite:
            raise bad_argument(f"{args.out} exists (--overwrite replaces it)")
        for frames in args.frames:
            if not os.path.isdir(os.path.join(frames, "detections_3d")):
                raise bad_argument(f"{frames} holds no detections_3d/: the labelled frames "
                                   "folder bag_to_files (or label_cuboids) writes")
        if args.config:
            existing_file(args.config, "config")
        positive_number(str(args.max_range), "--max-range")
        args.sensor = sensor_option(args.sensor, None)
        args.sensor_height = positive_number(args.sensor_height, "--sensor-height")
        args.azimuth_step = positive_number(args.azimuth_step, "--azimuth-step")
        args.prior_classes = args.prior_classes or None
        candidates = SWEEPS * sum(len(values) for values in TUNED.values())
        reporter = None if args.quiet else progress.Reporter(TOOL, unit="fits at most")
        with tempfile.TemporaryDirectory(prefix=f"{TOOL}-") as scratch:
            tuning = Tuning(args, scratch)
            start, best, chosen = tune(tuning, reporter, candidates)
            evidence = tuning.evidence(chosen)
        if reporter:
            reporter.finish()
        write_file(args.out, written(args, start, best, chosen, evidence).encode(),
                   "vehicle decision")
        print(f"{TOOL}: F1 on the labelled frames: zero-shot {start[0]:.3f}, tuned "
              f"{best[0]:.3f} ({', '.join(f'{k} {v}' for k, v in evidence.items()) or 'no change'}); "
              f"{tuning.runs} fits; wrote {args.out}")
        return 0

    return run_main(TOOL, body, (StageError, ConfigError, OutputError, OSError, yaml.YAMLError))
