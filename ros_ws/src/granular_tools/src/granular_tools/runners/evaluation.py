"""run_evaluation: models from train drives, every method on a test drive's objects, a report.

OUT/train    run_pipeline on the train bag (frames, objects N10, models + pictures); with
             several train bags, each bag's frames and objects in OUT/train/drive-<k>, their
             objects together in OUT/train/objects and the models built from those
OUT/test     run_pipeline on the test bag (frames, objects at every N_thresh)
OUT/classifiers  <method>.yml: the supervised classifiers, trained on the train objects;
             svm_fitness_training/: the registrations svm_fitness learns from
OUT/results  <method>[_<preset>]/N<thresh>.json from the classify tools (no suffix for the
             report's preset)
OUT/report   make_report: summary.json, confusion matrices, plots, index.md; intervals and
             per-track accuracy over the test drive's vehicles
"""
import argparse
import json
import os
import shutil
import time

from ..evaluation import report
from ..evaluation.instances import with_interval
from ..evaluation.methods import (DEFAULT_FITNESS_FROM, DEFAULT_PRESETS, DEFAULT_SUPERVISED,
                                  PRESETS, REGISTRATION_METHODS, SUPERVISED_METHODS)
from ..evaluation.metrics import ResultsError
from ..output import (OutputError, OutputFolder, check_output_folder, claimed_folder, resolve,
                      run_main)
from ..pcd import CloudError
from . import box_free_evaluation, pipeline
from .stages import StageError, add_runner_options, bad_argument, failure_marker, run_tool



def results_name(method, preset):
    """The report's name of a method run with a preset: the report's preset keeps the bare name."""
    return method if preset == "report" else f"{method}_{preset}"


def classify(method, models, objects, results_file, preset, config_file):
    command = ["rosrun", "granular_ros", "classify_registration", "--models", models,
               "--objects", objects, "--method", method, "--preset", preset,
               "--out", results_file]
    command += ["--config", config_file] if config_file else []
    run_tool(command, f"classify_registration --method {method}")


def classes_option(models):
    """train_classifier's --classes: the classes that got a model, when build_models left some
    out (too few objects or points), so that the classifiers learn the classes the registration
    methods can answer; none when every class has its model."""
    with open(os.path.join(models, "models.json"), encoding="utf-8") as stream:
        document = json.load(stream)
    left_out = document.get("left_out") or {}
    kept = sorted(set(document["classes"]) - set(left_out))
    return ["--classes", ",".join(kept)] if left_out else []


def train_and_classify(method, train_objects, test_run, classifiers, results, config_file,
                       models):
    """A supervised method: trained once on the train drive (the classes with models), then
    every test set."""
    model = os.path.join(classifiers, f"{method}.yml")
    command = ["rosrun", "granular_ros", "train_classifier", "--objects", train_objects,
               "--method", method, "--out", model] + classes_option(models)
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


def train_and_classify_fitness(fitness_from, models, train_objects, test_run, classifiers,
                               results, config_file, registration_config):
    """svm_fitness: the train drive's objects registered with each method it learns from, the
    SVM trained on those results and the objects' point histograms, then every test set from
    the test drive's own results and objects."""
    training = os.path.join(classifiers, "svm_fitness_training")
    os.makedirs(training, exist_ok=True)
    train_results = []
    for name in fitness_from:
        method, preset = split_results_name(name)
        print(f"run_evaluation: svm_fitness: registering the train drive's objects ({name})",
              flush=True)
        train_results.append(os.path.join(training, f"{name}.json"))
        classify(method, models, train_objects, train_results[-1], preset, registration_config)
    model = os.path.join(classifiers, "svm_fitness.yml")
    command = ["rosrun", "granular_ros", "train_classifier", "--method", "svm_fitness",
               "--registration", ",".join(train_results), "--objects", train_objects,
               "--out", model] + classes_option(models)
    command += ["--config", config_file] if config_file else []
    print("run_evaluation: training svm_fitness", flush=True)
    run_tool(command, "train_classifier --method svm_fitness")
    folder = os.path.join(results, "svm_fitness")
    os.makedirs(folder, exist_ok=True)
    for threshold in test_run.thresholds:
        print(f"run_evaluation: svm_fitness on N_thresh {threshold}", flush=True)
        test_results = [os.path.join(results, name, f"N{threshold}.json") for name in fitness_from]
        run_tool(["rosrun", "granular_ros", "classify_supervised", "--model", model,
                  "--registration", ",".join(test_results),
                  "--objects", test_run.objects_of(threshold),
                  "--out", os.path.join(folder, f"N{threshold}.json")],
                 "classify_supervised (svm_fitness)")


def split_results_name(name):
    """'icp_nl_tuned' -> ('icp_nl', 'tuned'); a bare method is the report's preset."""
    for preset in PRESETS:
        if preset != "report" and name.endswith(f"_{preset}"):
            return name[:-len(preset) - 1], preset
    return name, "report"


def check_methods(methods, supervised, presets, fitness_from=DEFAULT_FITNESS_FROM):
    for given, known, what in ((methods, REGISTRATION_METHODS, "method"),
                               (supervised, SUPERVISED_METHODS, "supervised method"),
                               (presets, PRESETS, "preset")):
        unknown = sorted(set(given) - set(known))
        if unknown:
            raise StageError("arguments", f"unknown {what}(s) {', '.join(unknown)}; known: "
                                          f"{', '.join(known)}", 2)
    if "svm_fitness" in supervised:
        run = {results_name(m, p) for m in methods for p in presets}
        absent = [name for name in fitness_from if name not in run]
        if not fitness_from or absent:
            raise StageError("arguments",
                             f"svm_fitness learns from the registrations "
                             f"{', '.join(fitness_from) or '(none given)'}, and "
                             f"{', '.join(absent) or 'none'} of them would not run: add their "
                             f"methods and presets, or change --fitness-from", 2)


def merge_objects(sources, bags, target, threshold, overwrite):
    """The objects folders `sources` (one per train bag, each with N<threshold>/ and its
    index.csv) as one: target/N<threshold>/ with every object file and one index.csv. Two
    drives holding an object file of the same name (the same bag given twice) are refused."""
    name = f"N{threshold}"
    with OutputFolder(target, "run_evaluation", overwrite) as folder:
        merged = os.path.join(folder.staging, name)
        os.mkdir(merged)
        from_bag = {}
        header, rows = None, []
        for source, bag in zip(sources, bags):
            objects = os.path.join(source, name)
            for entry in sorted(os.listdir(objects)):
                if not entry.endswith(".pcd"):
                    continue
                if entry in from_bag:
                    raise StageError("train objects", f"{entry} is an object of both "
                                     f"{from_bag[entry]} and {bag}: the same drive given twice?")
                from_bag[entry] = bag
                shutil.copyfile(os.path.join(objects, entry), os.path.join(merged, entry))
            with open(os.path.join(objects, "index.csv"), encoding="utf-8") as stream:
                lines = stream.read().splitlines(keepends=True)
            header = header or lines[0]
            rows += lines[1:]
        with open(os.path.join(merged, "index.csv"), "w", encoding="utf-8") as stream:
            stream.write(header + "".join(rows))
        folder.commit()
    print(f"run_evaluation: {len(from_bag)} train objects from {len(bags)} drives", flush=True)


def train_runs(train_bags, out, config_dir, overwrite):
    """The train bags' pipeline runs (each checked) and the run whose models and N10 objects
    the evaluation uses: with one bag, that bag's run into OUT/train, as run_pipeline; with
    several, one run per bag (frames and objects) into OUT/train/drive-<k>, and a models-only
    run into OUT/train over their merged objects."""
    train = os.path.join(out, "train")
    if len(train_bags) == 1:
        run = pipeline.PipelineRun(bag=train_bags[0], out=train, thresholds=(10,),
                                   models_from=10, config_dir=config_dir,
                                   overwrite=overwrite).checked()
        return [], run
    if len(set(map(os.path.realpath, train_bags))) < len(train_bags):
        raise bad_argument("--train-bag names one bag twice: its objects would count twice")
    drives = [pipeline.PipelineRun(bag=bag, out=os.path.join(train, f"drive-{k}"),
                                   stages=("frames", "objects"), thresholds=(10,),
                                   config_dir=config_dir, overwrite=overwrite).checked()
              for k, bag in enumerate(train_bags, 1)]
    models = pipeline.PipelineRun(bag=train_bags[0], out=train, stages=("models",),
                                  thresholds=(10,), models_from=10, config_dir=config_dir,
                                  overwrite=overwrite).checked()
    try:
        check_output_folder(models.objects_folder, overwrite)
    except OutputError as error:
        raise bad_argument(str(error)) from error
    return drives, models


def evaluate(train_bags, test_bag, out, methods, thresholds, presets, config_dir, overwrite,
             supervised=DEFAULT_SUPERVISED, fitness_from=DEFAULT_FITNESS_FROM):
    """Every stage of the evaluation into `out`; every argument checked before the first.
    `train_bags`: one or more drives the models and the supervised classifiers learn from."""
    check_methods(methods, supervised, presets, fitness_from)
    drive_runs, train_run = train_runs(train_bags, out, config_dir, overwrite)
    test_run = pipeline.PipelineRun(bag=test_bag, out=os.path.join(out, "test"),
                                    stages=("frames", "objects"), thresholds=thresholds,
                                    config_dir=config_dir, overwrite=overwrite).checked()
    with claimed_folder(out, "run_evaluation") as out, failure_marker(out):
        if drive_runs:
            with claimed_folder(train_run.out, "run_evaluation"):
                for drive_run in drive_runs:
                    pipeline.run(drive_run)
                merge_objects([run.objects_folder for run in drive_runs], train_bags,
                              train_run.objects_folder, 10, overwrite)
                pipeline.models_stage(train_run)
        else:
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
            if method == "svm_fitness":
                train_and_classify_fitness(fitness_from, models, train_objects, test_run,
                                           classifiers, results,
                                           test_run.config_file("supervised.yaml"),
                                           test_run.config_file("classification.yaml"))
            else:
                train_and_classify(method, train_objects, test_run, classifiers, results,
                                   test_run.config_file("supervised.yaml"), models)
        try:
            return report.make_report(results, os.path.join(out, "report"),
                                      os.path.join(models, "pictures"),
                                      train_objects if "knn" in supervised else None,
                                      test_run.objects_folder, overwrite=True)
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
        description="Build class models from train drives, classify a separate test drive's "
                    "objects at every N_thresh with every method, and write the report "
                    "(OUT/report/index.md).")
    parser.add_argument("--train-bag", required=True, metavar="BAG[,BAG...]",
                        help="the drive the class models and the supervised classifiers learn "
                             "from; several, comma-separated, learn from all of them (more "
                             "views of each class)")
    parser.add_argument("--test-bag", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--methods", default=",".join(REGISTRATION_METHODS),
                        help="registration methods, comma-separated (default: %(default)s)")
    parser.add_argument("--supervised", default=",".join(DEFAULT_SUPERVISED),
                        help="supervised methods, comma-separated, trained on the train "
                             "drive's objects at N_thresh 10; '' for none (default: "
                             "%(default)s)")
    parser.add_argument("--fitness-from", default=",".join(DEFAULT_FITNESS_FROM),
                        metavar="NAME,NAME,...",
                        help="the registrations svm_fitness learns from, as the results are "
                             "named (<method>_tuned, or <method> for the report's preset); "
                             "each must also run (default: %(default)s)")
    parser.add_argument("--n-thresh", default="10,50,100,300,500", metavar="N,N,...")
    parser.add_argument("--presets", default=",".join(DEFAULT_PRESETS),
                        help="registration parameter presets of config/classification.yaml, "
                             "comma-separated; each method runs with each (default: "
                             "%(default)s)")
    parser.add_argument("--boxes", default="detections",
                        help="detections (the drives' boxes: every method at every N_thresh) "
                             "or segment (the box-free evaluation: svm_fitness trained on the "
                             "train drive's box-free objects, then the test drive segmented, "
                             "fitted, named and tracked without its boxes and scored against "
                             "them; --methods, --supervised, --presets and --n-thresh unused; "
                             "docs/tracking.md); default %(default)s")
    parser.add_argument("--config-dir", metavar="FOLDER")
    add_runner_options(parser)
    args = parser.parse_args(argv)
    started = time.monotonic()

    def body():
        out = resolve(args.out, args.relative_to)
        train_bags = [resolve(bag, args.relative_to) for bag in args.train_bag.split(",") if bag]
        if not train_bags:
            raise bad_argument("--train-bag: no bag given")
        if args.boxes not in ("detections", "segment"):
            raise bad_argument(f"--boxes must be detections or segment, got '{args.boxes}'")
        if args.boxes == "segment":
            report_file = box_free_evaluation.evaluate_box_free(
                train_bags, resolve(args.test_bag, args.relative_to), out,
                resolve(args.config_dir, args.relative_to), args.overwrite)
            print(f"run_evaluation: done in {time.monotonic() - started:.1f} s; report: "
                  f"{os.path.join(os.path.dirname(report_file), 'index.md')}")
            return 0
        summary = evaluate(train_bags,
                           resolve(args.test_bag, args.relative_to), out,
                           [m for m in args.methods.split(",") if m],
                           pipeline.thresholds_from(args.n_thresh),
                           [p for p in args.presets.split(",") if p],
                           resolve(args.config_dir, args.relative_to), args.overwrite,
                           [m for m in args.supervised.split(",") if m],
                           [m for m in args.fitness_from.split(",") if m])
        for method, by_threshold in sorted(summary.items()):
            cells = ", ".join(f"{k} {accuracy_text(v)}" for k, v in
                              sorted(by_threshold.items(), key=lambda kv: int(kv[0][1:])))
            print(f"run_evaluation: {method}: accuracy {cells}")
        print("run_evaluation: [95 % interval over the test drive's vehicles and pedestrians]")
        print(f"run_evaluation: done in {time.monotonic() - started:.1f} s; report: "
              f"{os.path.join(out, 'report', 'index.md')}")
        return 0

    return run_main("run_evaluation", body, (StageError, OSError, ValueError))
