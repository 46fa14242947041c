"""run_pipeline: the pipeline's stages in order, each writing one sub-folder of OUT.

OUT/frames   bag to files (PCD + JSON pairs)
OUT/objects  per-object clouds in their own frame, one folder N<thresh> per threshold
OUT/models   one filtered model cloud per class (from OUT/objects/N<models-from>), with pictures
"""
import argparse
import os
import subprocess
import sys
import time

from . import progress
from .bag_to_files.config import BagToFilesConfig
from .bag_to_files.frames import OutputError
from .bag_to_files.offline import BagError, convert_into_new_folder
from .bag_to_files.pcd import CloudError
from .config_loading import ConfigError, load_yaml_over
from .models import pictures

STAGES = ("frames", "objects", "models")


class StageError(RuntimeError):
    pass


def stage_config(config_dir, name):
    """The config file of a stage when a config folder is given and holds it."""
    path = os.path.join(config_dir, name) if config_dir else None
    return path if path and os.path.exists(path) else None


def run_tool(command, what):
    """Run a stage's tool; its own messages reach the user, a failure stops the pipeline."""
    if subprocess.run(command).returncode != 0:
        raise StageError(f"{what} failed (its message is above)")


def frames_stage(bag, out, config_dir, overwrite):
    config = BagToFilesConfig()
    config_file = stage_config(config_dir, "bag_to_files.yaml")
    if config_file:
        config = load_yaml_over(config, config_file)
    reporter = progress.Reporter("frames", unit="messages")
    stats = convert_into_new_folder(bag, out, config.check(), overwrite, reporter)
    reporter.finish()
    print(f"frames: {stats.summary(config.slop)}", flush=True)


def objects_stage(frames, out, thresholds, config_dir, overwrite):
    # extract_objects writes one threshold's objects straight into its --out folder, and
    # several thresholds into N<thresh>/ sub-folders; the pipeline always wants the latter.
    values = [t for t in thresholds.split(",") if t]
    target = os.path.join(out, f"N{values[0]}") if len(values) == 1 else out
    command = ["rosrun", "granular_ros", "extract_objects", "--in", frames, "--out", target,
               "--n-thresh", thresholds]
    config_file = stage_config(config_dir, "extraction.yaml")
    command += ["--config", config_file] if config_file else []
    command += ["--overwrite"] if overwrite else []
    run_tool(command, "extract_objects")


def models_stage(objects, out, method, config_dir, overwrite):
    command = ["rosrun", "granular_ros", "build_models", "--objects", objects, "--out", out,
               "--method", method]
    config_file = stage_config(config_dir, "models.yaml")
    command += ["--config", config_file] if config_file else []
    command += ["--overwrite"] if overwrite else []
    run_tool(command, "build_models")
    if pictures.main(["--models", out]) != 0:
        raise StageError("render_models failed (its message is above)")


def run(bag, out, stages=STAGES, thresholds="10,50,100,300,500", models_from=10,
        model_method="plain", config_dir=None, overwrite=False):
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    frames, objects = os.path.join(out, "frames"), os.path.join(out, "objects")
    if "frames" in stages:
        frames_stage(bag, frames, config_dir, overwrite)
    if "objects" in stages:
        objects_stage(frames, objects, thresholds, config_dir, overwrite)
    if "models" in stages:
        if str(models_from) not in thresholds.split(","):
            raise StageError(f"--models-from {models_from} is not one of --n-thresh {thresholds}")
        models_stage(os.path.join(objects, f"N{models_from}"), os.path.join(out, "models"),
                     model_method, config_dir, overwrite)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="run_pipeline",
        description="Run granular's stages on a bag, in order: OUT/frames (bag to PCD + JSON "
                    "pairs), OUT/objects/N<thresh> (per-object clouds), OUT/models (class "
                    "models and their pictures).")
    parser.add_argument("--bag", required=True)
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--stages", default=",".join(STAGES),
                        help="comma-separated subset of %(default)s (later stages read the "
                             "earlier ones' folders)")
    parser.add_argument("--n-thresh", default="10,50,100,300,500", metavar="N,N,...",
                        help="minimum points per object, one objects folder each "
                             "(default: %(default)s)")
    parser.add_argument("--models-from", type=int, default=10, metavar="N",
                        help="build the models from OUT/objects/N<N> (default: %(default)s, "
                             "as the report)")
    parser.add_argument("--model-method", choices=("plain", "icp"), default="plain",
                        help="concatenate objects as they are, or ICP-aligned "
                             "(default: %(default)s)")
    parser.add_argument("--config-dir", metavar="FOLDER",
                        help="folder with bag_to_files.yaml, extraction.yaml, models.yaml "
                             "(default: the tools' built-in defaults)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace results already in OUT")
    args = parser.parse_args(argv)
    stages = [s for s in args.stages.split(",") if s]
    unknown = sorted(set(stages) - set(STAGES))
    if unknown:
        parser.error(f"unknown stage(s) {', '.join(unknown)}; stages: {', '.join(STAGES)}")
    started = time.monotonic()
    try:
        run(args.bag, args.out, stages, args.n_thresh, args.models_from, args.model_method,
            args.config_dir, args.overwrite)
    except (BagError, CloudError, OutputError, ConfigError, StageError, ValueError,
            OSError) as error:
        print(f"run_pipeline: error: {error}", file=sys.stderr)
        return 1
    print(f"run_pipeline: done in {time.monotonic() - started:.1f} s; results in "
          f"{os.path.abspath(args.out)}")
    return 0
