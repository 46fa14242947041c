"""run_evaluation: models from a train drive, every method on a test drive's objects, a report.

OUT/train    run_pipeline on the train bag (frames, objects N10, models + pictures)
OUT/test     run_pipeline on the test bag (frames, objects at every N_thresh)
OUT/classifiers  <method>.yml: the supervised classifiers, trained on the train drive's objects
OUT/results  <method>[_<preset>]/N<thresh>.json from the classify tools (no suffix for the
             report's preset)
OUT/report   make_report: summary.json, confusion matrices, plots, index.md
"""
import argparse
import os
import sys
import time

from .. import pipeline
from ..bag_to_files.frames import OutputError
from ..bag_to_files.offline import BagError
from ..bag_to_files.pcd import CloudError
from ..config_loading import ConfigError
from . import report
from .metrics import ResultsError

REGISTRATION_METHODS = ("icp", "icp_nl", "ndt")
SUPERVISED_METHODS = ("knn", "svm", "svm_esf")
PRESETS = ("report", "tuned")


def results_name(method, preset):
    """The report's name of a method run with a preset: the report's preset keeps the bare name."""
    return method if preset == "report" else f"{method}_{preset}"


def classify(method, models, objects, results_file, preset, config_dir):
    if method not in REGISTRATION_METHODS:
        raise pipeline.StageError(f"unknown method {method}; methods: "
                                  f"{', '.join(REGISTRATION_METHODS)}")
    command = ["rosrun", "granular_ros", "classify_registration", "--models", models,
               "--objects", objects, "--method", method, "--preset", preset,
               "--out", results_file]
    config_file = pipeline.stage_config(config_dir, "classification.yaml")
    command += ["--config", config_file] if config_file else []
    pipeline.run_tool(command, f"classify_registration --method {method}")


def train_and_classify(method, train_objects, test_objects, classifiers, results, thresholds,
                       config_dir):
    """A supervised method: trained once on the train drive, then every test set."""
    model = os.path.join(classifiers, f"{method}.yml")
    command = ["rosrun", "granular_ros", "train_classifier", "--objects", train_objects,
               "--method", method, "--out", model]
    config_file = pipeline.stage_config(config_dir, "supervised.yaml")
    command += ["--config", config_file] if config_file else []
    print(f"run_evaluation: training {method}", flush=True)
    pipeline.run_tool(command, f"train_classifier --method {method}")
    folder = os.path.join(results, method)
    os.makedirs(folder, exist_ok=True)
    for threshold in thresholds.split(","):
        print(f"run_evaluation: {method} on N_thresh {threshold}", flush=True)
        pipeline.run_tool(["rosrun", "granular_ros", "classify_supervised", "--model", model,
                           "--objects", os.path.join(test_objects, f"N{threshold}"),
                           "--out", os.path.join(folder, f"N{threshold}.json")],
                          f"classify_supervised ({method})")


def evaluate(train_bag, test_bag, out, methods, thresholds, presets, config_dir, overwrite,
             supervised=SUPERVISED_METHODS):
    out = os.path.abspath(out)
    train, test = os.path.join(out, "train"), os.path.join(out, "test")
    pipeline.run(train_bag, train, pipeline.STAGES, "10", 10, "plain", config_dir, overwrite)
    pipeline.run(test_bag, test, ("frames", "objects"), thresholds, 10, "plain", config_dir,
                 overwrite)
    results = os.path.join(out, "results")
    for method in methods:
        for preset in presets:
            folder = os.path.join(results, results_name(method, preset))
            os.makedirs(folder, exist_ok=True)
            for threshold in thresholds.split(","):
                print(f"run_evaluation: {method} ({preset}) on N_thresh {threshold}", flush=True)
                classify(method, os.path.join(train, "models"),
                         os.path.join(test, "objects", f"N{threshold}"),
                         os.path.join(folder, f"N{threshold}.json"), preset, config_dir)
    train_objects = os.path.join(train, "objects", "N10")
    classifiers = os.path.join(out, "classifiers")
    os.makedirs(classifiers, exist_ok=True)
    for method in supervised:
        if method not in SUPERVISED_METHODS:
            raise pipeline.StageError(f"unknown supervised method {method}; methods: "
                                      f"{', '.join(SUPERVISED_METHODS)}")
        train_and_classify(method, train_objects, os.path.join(test, "objects"), classifiers,
                           results, thresholds, config_dir)
    return report.make_report(results, os.path.join(out, "report"),
                              os.path.join(train, "models", "pictures"),
                              train_objects if "knn" in supervised else None)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="run_evaluation",
        description="Build class models from a train drive, classify a separate test drive's "
                    "objects at every N_thresh with every method, and write the report "
                    "(OUT/report/index.md).")
    parser.add_argument("--train-bag", required=True)
    parser.add_argument("--test-bag", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--methods", default=",".join(REGISTRATION_METHODS),
                        help="registration methods, comma-separated (default: %(default)s)")
    parser.add_argument("--supervised", default=",".join(SUPERVISED_METHODS),
                        help="supervised methods, comma-separated, trained on the train "
                             "drive's objects at N_thresh 10; '' for none (default: "
                             "%(default)s)")
    parser.add_argument("--n-thresh", default="10,50,100,300,500", metavar="N,N,...")
    parser.add_argument("--presets", default=",".join(PRESETS),
                        help="registration parameter presets of config/classification.yaml, "
                             "comma-separated; each method runs with each (default: "
                             "%(default)s)")
    parser.add_argument("--config-dir", metavar="FOLDER")
    parser.add_argument("--overwrite", action="store_true")
    args = parser.parse_args(argv)
    started = time.monotonic()
    try:
        summary = evaluate(args.train_bag, args.test_bag, args.out,
                           [m for m in args.methods.split(",") if m], args.n_thresh,
                           [p for p in args.presets.split(",") if p], args.config_dir,
                           args.overwrite, [m for m in args.supervised.split(",") if m])
    except (BagError, CloudError, OutputError, ConfigError, ResultsError,
            pipeline.StageError, ValueError, OSError) as error:
        print(f"run_evaluation: error: {error}", file=sys.stderr)
        return 1
    for method, by_threshold in sorted(summary.items()):
        cells = ", ".join(f"{k} {v['accuracy']:.3f}" for k, v in
                          sorted(by_threshold.items(), key=lambda kv: int(kv[0][1:])))
        print(f"run_evaluation: {method}: accuracy {cells}")
    print(f"run_evaluation: done in {time.monotonic() - started:.1f} s; report: "
          f"{os.path.join(os.path.abspath(args.out), 'report', 'index.md')}")
    return 0
