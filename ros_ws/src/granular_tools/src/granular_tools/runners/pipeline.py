"""run_pipeline: the pipeline's stages in order, each writing one sub-folder of OUT.

OUT/frames   bag to files (PCD + JSON pairs; clouds only for a bag without detections)
OUT/cuboids  with boxes "segment": fit_cuboids' cuboids of the box-free segments, labelled
             unknown, or named by the classifier --name-with gives (the bag's own boxes are
             never used)
OUT/objects  per-object clouds in their own frame, one folder N<thresh> per threshold, cropped
             in the bag's boxes or (boxes "segment") in the fitted cuboids
OUT/models   one filtered model cloud per class (from OUT/objects/N<models-from>), with pictures;
             not with boxes "segment", whose objects have no class yet

Every argument is checked before the first stage runs; a failing stage stops the run, leaves
OUT/FAILED naming it, and its exit status is the runner's.
"""
import argparse
import dataclasses
import os
import signal
import time

from ..models import pictures
from ..output import (Interrupted, OutputError, check_output_folder, claimed_folder, resolve,
                      run_main)
from .stages import (NAME_METHODS, ConfigFolder, StageError, add_runner_options,
                     add_sensor_options, bad_argument, bag_frames_config, check_naming,
                     existing_file, failure_marker, fit_command, frames_stage, positive_number,
                     run_tool, sensor_option)

STAGES = ("frames", "objects", "models")
STAGE_FOLDERS = {"frames": "frames", "objects": "objects", "models": "models"}
BOXES = ("detections", "segment")


@dataclasses.dataclass
class PipelineRun(ConfigFolder):
    """One run's arguments, checked (PipelineRun.checked) before any stage starts."""
    bag: str
    out: str
    stages: tuple = STAGES
    thresholds: tuple = (10, 50, 100, 300, 500)
    models_from: int = 10
    model_method: str = "plain"
    config_dir: str = None
    overwrite: bool = False
    boxes: str = "detections"
    sensor: str = None           # config/sensors/ name, a sensor file or auto
    sensor_height: float = None  # boxes "segment": the sensor above the road (m) ...
    azimuth_step: float = None   # ... and its angle between returns (deg)
    prior_classes: str = None    # ... and the cuboids' size priors
    name_with: str = None        # ... and the classifier that names them (run_cuboids') ...
    name_models: str = None      # ... its models folder or classifier file ...
    class_models: str = None     # ... and, for svm_fitness, the models it learnt from

    @property
    def objects_folder(self):
        return os.path.join(self.out, "objects")

    def objects_of(self, threshold):
        return os.path.join(self.objects_folder, f"N{threshold}")

    def checked(self):
        """Raise StageError("arguments", ...) (exit 2) for anything that would fail later."""
        unknown = sorted(set(self.stages) - set(STAGES))
        if unknown or not self.stages:
            raise bad_argument(f"unknown stage(s) {', '.join(unknown) or '(none given)'}; "
                               f"stages: {', '.join(STAGES)}")
        if not self.thresholds or any(t < 1 for t in self.thresholds):
            raise bad_argument("n_thresh must be a list of positive whole numbers of points")
        if "models" in self.stages and self.models_from not in self.thresholds:
            raise bad_argument(f"models_from {self.models_from} is not one of n_thresh "
                               f"{','.join(map(str, self.thresholds))}")
        if self.boxes not in BOXES:
            raise bad_argument(f"boxes must be {' or '.join(BOXES)}, got '{self.boxes}'")
        if self.boxes == "segment" and "models" in self.stages:
            raise bad_argument("boxes:=segment gives objects labelled unknown, of which no class "
                               "models can be built: run the stages frames,objects "
                               "(--stages frames,objects), then classify the objects with a "
                               "classifier trained on labelled drives")
        if self.name_with and self.boxes != "segment":
            raise bad_argument("name_with names the cuboids of boxes:=segment; the bag's boxes "
                               "carry their labels")
        check_naming(self.name_with, self.name_models, self.class_models)
        if self.model_method not in ("plain", "icp"):
            raise bad_argument(f"model_method must be plain or icp, got '{self.model_method}'")
        if "frames" in self.stages:
            existing_file(self.bag, "bag")
        if self.config_dir and not os.path.isdir(self.config_dir):
            raise bad_argument(f"config folder {self.config_dir} not found")
        folders = [STAGE_FOLDERS[stage] for stage in self.stages]
        folders += ["cuboids"] if self.boxes == "segment" and "objects" in self.stages else []
        for folder in folders:
            try:
                check_output_folder(os.path.join(self.out, folder), self.overwrite)
            except OutputError as error:
                raise bad_argument(str(error)) from error
        return self


def pipeline_frames_stage(run):
    config, boxed = bag_frames_config(run.bag, run.config_file("bag_to_files.yaml"))
    if not boxed and run.boxes != "segment":
        raise StageError("frames", f"{run.bag} has no {config.detections_topic}: a bag without "
                                   "boxes runs with boxes:=segment (--boxes segment)")
    frames_stage(run.bag, os.path.join(run.out, "frames"),
                 dataclasses.replace(config, clouds_only=not boxed), run.overwrite)


def cuboids_stage(run):
    """boxes "segment": the frames' boxes are the cuboids fitted to their segments."""
    run_tool(fit_command(run, os.path.join(run.out, "frames"), os.path.join(run.out, "cuboids"),
                         "segment", naming=(run.name_with, run.name_models, run.class_models)),
             "cuboids (fit_cuboids)")


def objects_stage(run):
    if run.boxes == "segment":
        cuboids_stage(run)
    # OUT/objects holds N<thresh>/ whatever thresholds are given, so that it is always one
    # folder extract_objects wrote (and may replace).
    thresholds = ",".join(map(str, run.thresholds))
    command = ["rosrun", "granular_ros", "extract_objects", "--in",
               os.path.join(run.out, "frames"), "--out", run.objects_folder, "--n-thresh",
               thresholds, "--threshold-folders"]
    command += ["--boxes", os.path.join(run.out, "cuboids")] if run.boxes == "segment" else []
    config_file = run.config_file("extraction.yaml")
    command += ["--config", config_file] if config_file else []
    command += ["--overwrite"] if run.overwrite else []
    run_tool(command, "objects (extract_objects)")


def models_stage(run):
    models = os.path.join(run.out, "models")
    command = ["rosrun", "granular_ros", "build_models", "--objects",
               run.objects_of(run.models_from), "--out", models, "--method", run.model_method]
    config_file = run.config_file("models.yaml")
    command += ["--config", config_file] if config_file else []
    command += ["--overwrite"] if run.overwrite else []
    run_tool(command, "models (build_models)")
    status = pictures.render_folder(models, overwrite=True)
    if status - 128 in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        # The pictures were interrupted: the run is, not failed (FAILED says so, exit 130/143).
        raise Interrupted(status - 128)
    if status != 0:
        raise StageError("models (render_models)", "failed (its message is above)", status)


def run(pipeline_run):
    """Run the stages of a PipelineRun into its OUT, which is locked meanwhile."""
    pipeline_run = pipeline_run.checked()
    with claimed_folder(pipeline_run.out, "run_pipeline") as out:
        with failure_marker(out):
            for stage, action in (("frames", pipeline_frames_stage), ("objects", objects_stage),
                                  ("models", models_stage)):
                if stage in pipeline_run.stages:
                    action(pipeline_run)


def thresholds_from(text):
    """"10,50" as (10, 50); a StageError (exit 2) naming the text otherwise."""
    try:
        values = tuple(int(item) for item in text.split(",") if item.strip())
    except ValueError:
        values = ()
    if not values or any(v < 1 for v in values):
        raise StageError("arguments", f"n_thresh '{text}' is not a comma-separated list of "
                                      "positive whole numbers, e.g. 10,50,100", 2)
    return values


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="run_pipeline",
        description="Run granular's stages on a bag, in order: OUT/frames (bag to PCD + JSON "
                    "pairs), OUT/objects/N<thresh> (per-object clouds), OUT/models (class "
                    "models and their pictures). Every argument is checked before the first "
                    "stage; a failing stage stops the run, leaves OUT/FAILED naming it and "
                    "gives its exit status (2: bad arguments; 130/143: interrupted).")
    parser.add_argument("--bag", required=True)
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--stages",
                        help=f"comma-separated subset of {','.join(STAGES)} (later stages read "
                             "the earlier ones' folders; default: all, frames,objects with "
                             "--boxes segment)")
    parser.add_argument("--n-thresh", default="10,50,100,300,500", metavar="N,N,...",
                        help="minimum points per object, one objects folder each "
                             "(default: %(default)s)")
    parser.add_argument("--models-from", default="10", metavar="N",
                        help="build the models from OUT/objects/N<N> (default: %(default)s, "
                             "as the report)")
    parser.add_argument("--model-method", default="plain",
                        help="plain (objects as they are) or icp (ICP-aligned) concatenation "
                             "(default: %(default)s)")
    parser.add_argument("--config-dir", metavar="FOLDER",
                        help="folder with bag_to_files.yaml, extraction.yaml, models.yaml "
                             "(default: the tools' built-in defaults)")
    parser.add_argument("--boxes", default="detections",
                        help="detections (the bag's boxes) or segment (cuboids fitted to the "
                             "box-free segments into OUT/cuboids, for bags without boxes; "
                             "stages frames,objects only); default %(default)s")
    add_sensor_options(parser)  # with --boxes segment
    parser.add_argument("--name-with", default="", metavar="METHOD",
                        help="--boxes segment: name each cuboid, and so each object, with this "
                             "classifier (" + ", ".join(NAME_METHODS) + "); default: unknown")
    parser.add_argument("--name-models", default="", metavar="PATH",
                        help="--name-with: the class models folder (icp, icp_nl, ndt) or the "
                             "train_classifier file (the others)")
    parser.add_argument("--class-models", default="", metavar="FOLDER",
                        help="--name-with svm_fitness: the class models it learnt from")
    add_runner_options(parser)
    args = parser.parse_args(argv)
    started = time.monotonic()

    def body():
        try:
            models_from = int(args.models_from)
        except ValueError:
            raise StageError("arguments", f"models_from '{args.models_from}' is not a whole "
                                          "number", 2) from None
        pipeline_run = PipelineRun(
            bag=resolve(args.bag, args.relative_to), out=resolve(args.out, args.relative_to),
            stages=(tuple(s for s in args.stages.split(",") if s) if args.stages is not None
                    else STAGES[:2] if args.boxes == "segment" else STAGES),
            thresholds=thresholds_from(args.n_thresh), models_from=models_from,
            model_method=args.model_method,
            config_dir=resolve(args.config_dir, args.relative_to), overwrite=args.overwrite,
            boxes=args.boxes, sensor=sensor_option(args.sensor, args.relative_to),
            sensor_height=positive_number(args.sensor_height, "sensor_height"),
            azimuth_step=positive_number(args.azimuth_step, "azimuth_step"),
            prior_classes=args.prior_classes or None, name_with=args.name_with or None,
            name_models=resolve(args.name_models or None, args.relative_to),
            class_models=resolve(args.class_models or None, args.relative_to))
        run(pipeline_run)
        print(f"run_pipeline: done in {time.monotonic() - started:.1f} s; results in "
              f"{pipeline_run.out}")
        return 0

    return run_main("run_pipeline", body, (StageError, OSError, ValueError))
