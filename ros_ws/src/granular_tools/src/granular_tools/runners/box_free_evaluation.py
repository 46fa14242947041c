"""run_evaluation --boxes segment: the box-free evaluation (docs/tracking.md).

OUT/train/frames       bag to files of the train drive
OUT/train/cuboids      fit_cuboids: its segments' cuboids (the zero-shot vehicle decision)
OUT/train/labelled     label_box_free: those cuboids labelled by the true boxes they match
OUT/train/objects/N10  extract_objects: the labelled cuboids' points in their object frames
OUT/train/models       build_models: class models of those objects
OUT/classifiers        svm_fitness.yml trained on them (svm_fitness_training/: the
                       registrations it learns from)
OUT/test/frames        bag to files of the test drive (its boxes are truth only)
OUT/test/cuboids       fit_cuboids --track --name-with svm_fitness: segmented, fitted, named,
                       tracked, without the test drive's boxes
OUT/report             evaluate_cuboids --tracking against the test drive's boxes: the six
                       vehicle classes within 30 m with at least 50 points
"""
import dataclasses
import os

from ..evaluation.box_free_objects import label_box_free
from ..evaluation.methods import DEFAULT_FITNESS_FROM
from ..frames_folder import DetectionsError
from ..output import OutputError, check_output_folder, claimed_folder
from . import cuboids
from .stages import (SIMULATOR_SENSOR, StageError, bad_argument, bag_frames_config,
                     failure_marker, fit_command, frames_stage, run_tool)

# The scoring: the simulator's vehicles near enough to be seen well.
VEHICLES = tuple(SIMULATOR_SENSOR["prior_classes"].split(","))
MAX_RANGE_M = 30
MIN_POINTS = 50


def _run(config_dir, overwrite):
    """The sensor, priors and config of the runners (a CuboidsRun serves fit_command)."""
    return cuboids.CuboidsRun(bag="", out="", config_dir=config_dir, overwrite=overwrite,
                              sensor=SIMULATOR_SENSOR["sensor"],
                              prior_classes=SIMULATOR_SENSOR["prior_classes"])


def check(train_bags, test_bag, out, config_dir, overwrite):
    if len(train_bags) != 1:
        raise bad_argument("boxes segment trains on one drive: give one --train-bag")
    for bag in (train_bags[0], test_bag):
        if not os.path.isfile(bag):
            raise bad_argument(f"bag {bag} not found")
    for name in ("train/frames", "train/cuboids", "train/labelled", "train/objects",
                 "train/models", "classifiers", "test/frames", "test/cuboids", "report"):
        try:
            check_output_folder(os.path.join(out, name), overwrite)
        except OutputError as error:
            raise bad_argument(str(error)) from error


def frames(bag, folder, config_dir, overwrite):
    config, boxed = bag_frames_config(bag, _run(config_dir, overwrite)
                                      .config_file("bag_to_files.yaml"))
    if not boxed:
        raise StageError("frames", f"{bag} has no {config.detections_topic}: the box-free "
                                   "evaluation trains on a drive's boxes and scores against them")
    frames_stage(bag, folder, config, overwrite)


def train(bag, out, config_dir, overwrite):
    """The train drive's box-free objects, their class models and svm_fitness on them; returns
    (classifier file, models folder)."""
    run = _run(config_dir, overwrite)
    folder = os.path.join(out, "train")
    os.makedirs(folder, exist_ok=True)
    frames(bag, os.path.join(folder, "frames"), config_dir, overwrite)
    run_tool(fit_command(run, os.path.join(folder, "frames"), os.path.join(folder, "cuboids"),
                         "segment"), "train cuboids (fit_cuboids)")
    try:
        labels, reversed_heading = label_box_free(
            os.path.join(folder, "frames"), os.path.join(folder, "cuboids"),
            os.path.join(folder, "labelled"), overwrite=overwrite)
    except (DetectionsError, OutputError) as error:
        raise StageError("train labels (label_box_free)", str(error)) from error
    print(f"run_evaluation: {sum(labels.values())} train cuboids matched a true box "
          f"({reversed_heading} facing the other way)", flush=True)
    objects = os.path.join(folder, "objects")
    command = ["rosrun", "granular_ros", "extract_objects", "--in",
               os.path.join(folder, "labelled"), "--out", objects, "--n-thresh", "10",
               "--threshold-folders"]
    command += ["--config", run.config_file("extraction.yaml")] \
        if run.config_file("extraction.yaml") else []
    run_tool(command + (["--overwrite"] if overwrite else []), "train objects (extract_objects)")
    models = os.path.join(folder, "models")
    command = ["rosrun", "granular_ros", "build_models", "--objects",
               os.path.join(objects, "N10"), "--out", models]
    command += ["--config", run.config_file("models.yaml")] \
        if run.config_file("models.yaml") else []
    run_tool(command + (["--overwrite"] if overwrite else []), "train models (build_models)")
    classifiers = os.path.join(out, "classifiers")
    training = os.path.join(classifiers, "svm_fitness_training")
    os.makedirs(training, exist_ok=True)
    results = []
    for name in DEFAULT_FITNESS_FROM:
        method = name[:-len("_tuned")]
        results.append(os.path.join(training, f"{name}.json"))
        command = ["rosrun", "granular_ros", "classify_registration", "--models", models,
                   "--objects", os.path.join(objects, "N10"), "--method", method,
                   "--preset", "tuned", "--out", results[-1]]
        command += ["--config", run.config_file("classification.yaml")] \
            if run.config_file("classification.yaml") else []
        print(f"run_evaluation: svm_fitness: registering the train drive's box-free objects "
              f"({name})", flush=True)
        run_tool(command, f"classify_registration --method {method}")
    classifier = os.path.join(classifiers, "svm_fitness.yml")
    command = ["rosrun", "granular_ros", "train_classifier", "--method", "svm_fitness",
               "--registration", ",".join(results), "--objects", os.path.join(objects, "N10"),
               "--out", classifier]
    command += ["--config", run.config_file("supervised.yaml")] \
        if run.config_file("supervised.yaml") else []
    print("run_evaluation: training svm_fitness on the box-free objects", flush=True)
    run_tool(command, "train_classifier --method svm_fitness")
    return classifier, models


def evaluate_box_free(train_bags, test_bag, out, config_dir, overwrite):
    """Every stage into `out`; returns the report's summary.json path."""
    check(train_bags, test_bag, out, config_dir, overwrite)
    with claimed_folder(out, "run_evaluation") as out, failure_marker(out):
        classifier, models = train(train_bags[0], out, config_dir, overwrite)
        test = dataclasses.replace(
            _run(config_dir, overwrite), bag=test_bag, out=os.path.join(out, "test"),
            track=True, name_with="svm_fitness", name_models=classifier, class_models=models)
        os.makedirs(test.out, exist_ok=True)
        frames(test_bag, test.folder("frames"), config_dir, overwrite)
        cuboids.cuboids_stage(test)
        command = ["rosrun", "granular_tools", "evaluate_cuboids", "--truth",
                   test.folder("frames"), "--predicted", test.folder("cuboids"), "--out",
                   os.path.join(out, "report"), "--max-range", str(MAX_RANGE_M),
                   "--min-points", str(MIN_POINTS), "--labels", *VEHICLES, "--tracking"]
        run_tool(command + (["--overwrite"] if overwrite else []), "report (evaluate_cuboids)")
    return os.path.join(out, "report", "summary.json")
