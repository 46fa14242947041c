"""run_evaluation: models from a train drive, every method on a test drive's objects, a report.

OUT/train    run_pipeline on the train bag (frames, objects N10, models + pictures)
OUT/test     run_pipeline on the test bag (frames, objects at every N_thresh)
OUT/classifiers  <method>.yml: the supervised classifiers, trained on the train drive's objects
OUT/results  <method>[_<preset>]/N<thresh>.json from the classify tools (no suffix for the
             report's preset)
OUT/report   make_report: summary.json, confusion matrices, plots, index.md; intervals and
             per-track accuracy over the test drive's vehicles
"""
import argparse
import os
import time

from .. import pipeline
from ..bag_to_files.pcd import CloudError
from ..output import OutputError, claimed_folder, run_main
from ..stages import StageError, add_runner_options, failure_marker, resolve, run_tool
from . import report
from .instances import with_interval
from .metrics import ResultsError

REGISTRATION_METHODS = ("icp", "icp_nl", "ndt")
SUPERVISED_METHODS = ("knn", "svm", "svm_esf")
# ESF takes 8 ms an object (docs/supervised.md), the demo's two minutes and 80 % of a frame's
# budget online, for the lowest accuracy: asked for by name only.
DEFAULT_SUPERVISED = ("knn", "svm")
PRESETS = ("report", "tuned")


def results_name(method, preset):
    """The report's name of a method run with a preset: the report's preset keeps the bare name."""
    return method if preset == "report" else f"{method}_{preset}"


def classify(method, models, objects, results_file, preset, config_file):
    command = ["rosrun", "granular_ros", "classify_registration", "--models", models,
               "--objects", objects, "--method", method, "--preset", preset,
               "--out", results_file]
    command += ["--config", config_file] if config_file else []
    run_tool(command, f"classify_registration --method {method}")


def train_and_classify(method, train_objects, test_run, classifiers, results, config_file):
    """A supervised method: trained once on the train drive, then every test set."""
    model = os.path.join(classifiers, f"{method}.yml")
    command = ["rosrun", "granular_ros", "train_classifier", "--objects", train_objects,
               "--method", method, "--out", model]
    command += ["--config", config_file] if config_file else []
    print(f"run_evaluation: training {method}", flush=True)
    run_tool(command, f"train_classifier --method {method}")
    folder = os.path.join(results, method)
    os.makedirs(folder, exist_ok=True)
    for threshold in test_run.thresholds:
        print(f"run_evaluation: {method} on N_thresh {threshold}", flush=True)
        run_tool(["rosrun", "granular_ros", "classify_supervised", "--model", model,
                  "--objects", test_run.objects_of(threshold),
                  "--out", os.path.join(folder, f"N{threshold}.json")],
                 f"classify_supervised ({method})")


def check_methods(methods, supervised, presets):
    for given, known, what in ((methods, REGISTRATION_METHODS, "method"),
                               (supervised, SUPERVISED_METHODS, "supervised method"),
                               (presets, PRESETS, "preset")):
        unknown = sorted(set(given) - set(known))
        if unknown:
            raise StageError("arguments", f"unknown {what}(s) {', '.join(unknown)}; known: "
                                          f"{', '.join(known)}", 2)


def evaluate(train_bag, test_bag, out, methods, thresholds, presets, config_dir, overwrite,
             supervised=DEFAULT_SUPERVISED):
    """Every stage of the evaluation into `out`; every argument checked before the first."""
    check_methods(methods, supervised, presets)
    train_run = pipeline.PipelineRun(bag=train_bag, out=os.path.join(out, "train"),
                                     thresholds=(10,), models_from=10, config_dir=config_dir,
                                     overwrite=overwrite).checked()
    test_run = pipeline.PipelineRun(bag=test_bag, out=os.path.join(out, "test"),
                                    stages=("frames", "objects"), thresholds=thresholds,
                                    config_dir=config_dir, overwrite=overwrite).checked()
    with claimed_folder(out, "run_evaluation") as out, failure_marker(out):
        pipeline.run(train_run)
        pipeline.run(test_run)
        results = os.path.join(out, "results")
        models = os.path.join(train_run.out, "models")
        for method in methods:
            for preset in presets:
                folder = os.path.join(results, results_name(method, preset))
                os.makedirs(folder, exist_ok=True)
                for threshold in thresholds:
                    print(f"run_evaluation: {method} ({preset}) on N_thresh {threshold}",
                          flush=True)
                    classify(method, models, test_run.objects_of(threshold),
                             os.path.join(folder, f"N{threshold}.json"), preset,
                             test_run.config_file("classification.yaml"))
        train_objects = train_run.objects_of(10)
        classifiers = os.path.join(out, "classifiers")
        os.makedirs(classifiers, exist_ok=True)
        for method in supervised:
            train_and_classify(method, train_objects, test_run, classifiers, results,
                               test_run.config_file("supervised.yaml"))
        try:
            return report.make_report(results, os.path.join(out, "report"),
                                      os.path.join(models, "pictures"),
                                      train_objects if "knn" in supervised else None,
                                      test_run.objects_folder)
        except (ResultsError, CloudError, OutputError) as error:
            raise StageError("report (make_report)", str(error)) from error


def accuracy_text(entry):
    """A summary entry's accuracy, with its interval over instances when it has one."""
    scores = (entry.get("instances") or {}).get("all")
    return with_interval(entry["accuracy"], scores["interval"]) if scores else \
        f"{entry['accuracy']:.3f}"


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
    parser.add_argument("--supervised", default=",".join(DEFAULT_SUPERVISED),
                        help="supervised methods, comma-separated, trained on the train "
                             "drive's objects at N_thresh 10; '' for none (default: "
                             "%(default)s)")
    parser.add_argument("--n-thresh", default="10,50,100,300,500", metavar="N,N,...")
    parser.add_argument("--presets", default=",".join(PRESETS),
                        help="registration parameter presets of config/classification.yaml, "
                             "comma-separated; each method runs with each (default: "
                             "%(default)s)")
    parser.add_argument("--config-dir", metavar="FOLDER")
    add_runner_options(parser)
    args = parser.parse_args(argv)
    started = time.monotonic()

    def body():
        out = resolve(args.out, args.relative_to)
        summary = evaluate(resolve(args.train_bag, args.relative_to),
                           resolve(args.test_bag, args.relative_to), out,
                           [m for m in args.methods.split(",") if m],
                           pipeline.thresholds_from(args.n_thresh),
                           [p for p in args.presets.split(",") if p],
                           resolve(args.config_dir, args.relative_to), args.overwrite,
                           [m for m in args.supervised.split(",") if m])
        for method, by_threshold in sorted(summary.items()):
            cells = ", ".join(f"{k} {accuracy_text(v)}" for k, v in
                              sorted(by_threshold.items(), key=lambda kv: int(kv[0][1:])))
            print(f"run_evaluation: {method}: accuracy {cells}")
        print("run_evaluation: [95 % interval over the test drive's vehicles and pedestrians]")
        print(f"run_evaluation: done in {time.monotonic() - started:.1f} s; report: "
              f"{os.path.join(out, 'report', 'index.md')}")
        return 0

    return run_main("run_evaluation", body, (StageError, OSError, ValueError))
