"""run_cuboids: cuboids fitted to a bag's objects, and scored when the bag carries boxes.

OUT/frames   bag to files (a bag without detections gives clouds only)
OUT/cuboids  fit_cuboids: one <stamp>.json per frame, in detections_3d's layout (with track:
             the cuboids of born tracks, with their track ids and velocities)
OUT/report   evaluate_cuboids against the bag's own boxes (only when the bag has them; with
             track: the tracking figures too)

With boxes segment the bag's boxes are truth only, never input: the objects are the box-free
segmentation's segments. With boxes detections the fitter starts from the bag's boxes (grown by
the config's margin, their headings unused). Every argument is checked before the first stage;
a failing stage stops the run, leaves OUT/FAILED naming it, and its exit status is the runner's.
"""
import argparse
import dataclasses
import os
import time

from ..output import OutputError, check_output_folder, claimed_folder, resolve, run_main
from .stages import (NAME_METHODS, ConfigFolder, StageError, add_runner_options,
                     add_sensor_options, bad_argument, bag_frames_config, check_naming,
                     existing_file, failure_marker, fit_command, frames_stage, positive_number,
                     run_tool, sensor_option)

BOXES = ("segment", "detections")
METHODS = ("geometric", "model", "rectangle")


@dataclasses.dataclass
class CuboidsRun(ConfigFolder):
    """One run's arguments, checked (CuboidsRun.checked) before any stage starts."""
    bag: str
    out: str
    boxes: str = "segment"
    method: str = None          # None: the config's
    models: str = None
    classifier: str = None      # the Background decision on segments
    config_dir: str = None
    sensor: str = None           # config/sensors/ name, a sensor file or auto
    sensor_height: float = None
    azimuth_step: float = None
    prior_classes: str = None
    max_range: float = None     # the report's truths: within this range (m) ...
    min_points: int = None      # ... and with at least this many points ...
    labels: tuple = ()          # ... and these labels (none: every label)
    track: bool = False         # track the cuboids (config_dir's tracking.yaml)
    name_with: str = None       # the classifier that names each cuboid (NAME_METHODS) ...
    name_models: str = None     # ... its models folder or classifier file ...
    class_models: str = None    # ... and, for svm_fitness, the models it learnt from
    allow_other_frames: bool = False  # fit_cuboids goes on past clouds not in the sensor's frame
    overwrite: bool = False

    def folder(self, name):
        return os.path.join(self.out, name)

    def checked(self):
        """Raise StageError("arguments", ...) (exit 2) for anything that would fail later."""
        if self.boxes not in BOXES:
            raise bad_argument(f"boxes must be {' or '.join(BOXES)}, got '{self.boxes}'")
        if self.method is not None and self.method not in METHODS:
            raise bad_argument(f"method must be one of {', '.join(METHODS)}, got '{self.method}'")
        if self.method == "model" and not self.models:
            raise bad_argument("the model method needs models (a models folder that "
                               "pipeline.launch wrote)")
        if self.classifier and self.boxes != "segment":
            raise bad_argument("a Background classifier decides on segments: it needs "
                               "boxes:=segment")
        if self.classifier:
            existing_file(self.classifier, "classifier")
        check_naming(self.name_with, self.name_models, self.class_models)
        if self.models and not os.path.isdir(self.models):
            raise bad_argument(f"models folder {self.models} not found")
        if self.config_dir and not os.path.isdir(self.config_dir):
            raise bad_argument(f"config folder {self.config_dir} not found")
        existing_file(self.bag, "bag")
        for name in ("frames", "cuboids", "report"):
            try:
                check_output_folder(self.folder(name), self.overwrite)
            except OutputError as error:
                raise bad_argument(str(error)) from error
        return self


def cuboids_stage(run):
    command = fit_command(run, run.folder("frames"), run.folder("cuboids"), run.boxes,
                          run.method, run.models, run.classifier, run.track,
                          (run.name_with, run.name_models, run.class_models))
    command += ["--allow-other-frames"] if run.allow_other_frames else []
    run_tool(command, "cuboids (fit_cuboids)")


def report_stage(run):
    command = ["rosrun", "granular_tools", "evaluate_cuboids", "--truth", run.folder("frames"),
               "--predicted", run.folder("cuboids"), "--out", run.folder("report")]
    for option, value in (("--max-range", run.max_range), ("--min-points", run.min_points)):
        command += [option, str(value)] if value is not None else []
    command += ["--labels", *run.labels] if run.labels else []
    command += ["--tracking"] if run.track else []
    command += ["--overwrite"] if run.overwrite else []
    run_tool(command, "report (evaluate_cuboids)")


def run(cuboids_run):
    """Run the stages of a CuboidsRun into its OUT, which is locked meanwhile."""
    cuboids_run = cuboids_run.checked()
    config, boxed = bag_frames_config(cuboids_run.bag,
                                      cuboids_run.config_file("bag_to_files.yaml"))
    if cuboids_run.boxes == "detections" and not boxed:
        raise StageError("arguments", f"{cuboids_run.bag} has no {config.detections_topic}: "
                                      "boxes:=detections needs a bag with boxes (boxes:=segment "
                                      "fits the segments of a clouds-only bag)", 2)
    with claimed_folder(cuboids_run.out, "run_cuboids") as out:
        with failure_marker(out):
            frames_stage(cuboids_run.bag, cuboids_run.folder("frames"),
                         dataclasses.replace(config, clouds_only=not boxed),
                         cuboids_run.overwrite)
            cuboids_stage(cuboids_run)
            if boxed:
                report_stage(cuboids_run)
            else:
                print("run_cuboids: the bag has no boxes, so no report", flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="run_cuboids",
        description="Fit cuboids to the objects of a bag: OUT/frames (bag to PCD + JSON pairs; "
                    "clouds only when the bag has no detections), OUT/cuboids (fit_cuboids: "
                    "<stamp>.json per frame in detections_3d's layout), and, when the bag "
                    "carries boxes, OUT/report (evaluate_cuboids against them; with --track the "
                    "tracking figures too). With --boxes "
                    "segment the bag's boxes are truth only, never input. Every argument is "
                    "checked before the first stage; a failing stage stops the run, leaves "
                    "OUT/FAILED naming it and gives its exit status (2: bad arguments; "
                    "130/143: interrupted).")
    parser.add_argument("--bag", required=True)
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--boxes", default="segment",
                        help="segment (the box-free segmentation's segments) or detections "
                             "(the bag's boxes, grown, headings unused); default %(default)s")
    parser.add_argument("--method", default="",
                        help="geometric, model or rectangle (default: the config's)")
    parser.add_argument("--models", default="", metavar="FOLDER",
                        help="class models (OUT/models of pipeline.launch) for --method model")
    parser.add_argument("--classifier", default="", metavar="FILE",
                        help="--boxes segment: the Background decision, a train_classifier file "
                             "trained with Background objects (extract_objects --background); "
                             "the segments it calls Background get no cuboid")
    parser.add_argument("--name-with", default="", metavar="METHOD",
                        help="name each cuboid with this classifier (" + ", ".join(NAME_METHODS) +
                             "): its points cropped in its object frame as a given box's are; "
                             "its label replaces the fitter's and --classifier's")
    parser.add_argument("--name-models", default="", metavar="PATH",
                        help="--name-with: the class models folder (icp, icp_nl, ndt) or the "
                             "train_classifier file (the others)")
    parser.add_argument("--class-models", default="", metavar="FOLDER",
                        help="--name-with svm_fitness: the class models it learnt from")
    parser.add_argument("--track", action="store_true",
                        help="track the cuboids from frame to frame (docs/tracking.md): only "
                             "the cuboids of born tracks are written, with their track ids and "
                             "velocities, and the report scores the tracks")
    parser.add_argument("--config-dir", metavar="FOLDER",
                        help="folder with bag_to_files.yaml, cuboids.yaml, ground.yaml, "
                             "segmentation.yaml, tracking.yaml (default: the tools' built-in "
                             "defaults)")
    add_sensor_options(parser)
    parser.add_argument("--allow-other-frames", action="store_true",
                        help="fit_cuboids goes on past clouds whose road is not where the "
                             "sensor's frame puts it (a world frame), naming each; without it "
                             "the first stops the run (docs/ground.md)")
    parser.add_argument("--max-range", default="", metavar="M",
                        help="report: only truths within M metres of the sensor")
    parser.add_argument("--min-points", default="", metavar="N",
                        help="report: only truths with at least N points")
    parser.add_argument("--labels", default="", metavar="LIST",
                        help="report: only truths with these labels, comma-separated")
    add_runner_options(parser)
    args = parser.parse_args(argv)
    started = time.monotonic()

    def body():
        cuboids_run = CuboidsRun(
            bag=resolve(args.bag, args.relative_to), out=resolve(args.out, args.relative_to),
            boxes=args.boxes, method=args.method or None,
            models=resolve(args.models or None, args.relative_to),
            classifier=resolve(args.classifier or None, args.relative_to),
            config_dir=resolve(args.config_dir, args.relative_to),
            sensor=sensor_option(args.sensor, args.relative_to),
            sensor_height=positive_number(args.sensor_height, "sensor_height"),
            azimuth_step=positive_number(args.azimuth_step, "azimuth_step"),
            prior_classes=args.prior_classes or None,
            max_range=positive_number(args.max_range, "max_range"),
            min_points=positive_number(args.min_points, "min_points", int),
            labels=tuple(label for label in args.labels.split(",") if label),
            track=args.track, allow_other_frames=args.allow_other_frames,
            name_with=args.name_with or None,
            name_models=resolve(args.name_models or None, args.relative_to),
            class_models=resolve(args.class_models or None, args.relative_to),
            overwrite=args.overwrite)
        run(cuboids_run)
        print(f"run_cuboids: done in {time.monotonic() - started:.1f} s; results in "
              f"{cuboids_run.out}")
        return 0

    return run_main("run_cuboids", body, (StageError, OSError, ValueError))
