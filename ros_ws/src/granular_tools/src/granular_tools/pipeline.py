"""run_pipeline: the pipeline's stages in order, each writing one sub-folder of OUT.

OUT/frames   bag to files (PCD + JSON pairs)
OUT/objects  per-object clouds in their own frame, one folder per N_thresh (extract_objects)
"""
import argparse
import os
import subprocess
import sys
import time

from . import progress
from .bag_to_files.config import BagToFilesConfig
from .bag_to_files.offline import BagError, convert_into_new_folder
from .bag_to_files.frames import OutputError
from .bag_to_files.pcd import CloudError
from .config_loading import ConfigError, load_yaml_over


class StageError(RuntimeError):
    pass


def frames_stage(bag, out, config_dir, overwrite):
    config = BagToFilesConfig()
    config_file = os.path.join(config_dir, "bag_to_files.yaml") if config_dir else None
    if config_file and os.path.exists(config_file):
        config = load_yaml_over(config, config_file)
    reporter = progress.Reporter("frames", unit="messages")
    stats = convert_into_new_folder(bag, out, config.check(), overwrite, reporter)
    reporter.finish()
    print(f"frames: {stats.summary(config.slop)}", flush=True)


def objects_stage(frames, out, thresholds, config_dir, overwrite):
    command = ["rosrun", "granular_ros", "extract_objects", "--in", frames, "--out", out,
               "--n-thresh", thresholds]
    config_file = os.path.join(config_dir, "extraction.yaml") if config_dir else None
    if config_file and os.path.exists(config_file):
        command += ["--config", config_file]
    if overwrite:
        command.append("--overwrite")
    if subprocess.run(command).returncode != 0:
        raise StageError("extract_objects failed (its message is above)")


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="run_pipeline",
        description="Run granular's stages on a bag, in order: OUT/frames (bag to PCD + JSON "
                    "pairs), OUT/objects (per-object clouds for each N_thresh).")
    parser.add_argument("--bag", required=True)
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--n-thresh", default="10,50,100,300,500", metavar="N,N,...",
                        help="minimum points per object, one objects folder each "
                             "(default: %(default)s)")
    parser.add_argument("--config-dir", metavar="FOLDER",
                        help="folder with bag_to_files.yaml and extraction.yaml "
                             "(default: the tools' built-in defaults)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace results already in OUT")
    args = parser.parse_args(argv)
    out = os.path.abspath(args.out)
    started = time.monotonic()
    try:
        os.makedirs(out, exist_ok=True)
        frames = os.path.join(out, "frames")
        frames_stage(args.bag, frames, args.config_dir, args.overwrite)
        objects_stage(frames, os.path.join(out, "objects"), args.n_thresh, args.config_dir,
                      args.overwrite)
    except (BagError, CloudError, OutputError, ConfigError, StageError, ValueError,
            OSError) as error:
        print(f"run_pipeline: error: {error}", file=sys.stderr)
        return 1
    print(f"run_pipeline: done in {time.monotonic() - started:.1f} s; results in {out}")
    return 0
