"""evaluate_many: the evaluation over several independent train/test drive pairs, pooled.

OUT/pair-<train seed>-<test seed>/{train,test}.bag   simulate_drive; train-<k>.bag: the pair's
                                                     k-th train drive (seed: train seed +
                                                     1000 (k - 1)) with --train-drives
OUT/pair-<train seed>-<test seed>/evaluation         run_evaluation (models, results, report);
                                                     evaluation-<K>-drives with K train drives
OUT/summary.json, OUT/index.md                       per method and N_thresh: the mean over the
                                                     pairs and its 95 % interval, per object and
                                                     per track, all classes and the four cars

One drive pair is a small, correlated sample (instances.py); independent pairs are what makes
a mean mean something. A pair whose evaluation is complete is reused, so that an interrupted
run goes on where it stopped (--overwrite runs every pair again).
"""
import argparse
import json
import os
import time

from ..evaluation.instances import (FOUR_CARS, PARTS, accuracy, instance_groups, instances_of,
                                    mean_interval, with_interval)
from ..evaluation.methods import DEFAULT_FITNESS_FROM, DEFAULT_SUPERVISED, REGISTRATION_METHODS
from ..evaluation.metrics import ResultsError, load_results
from ..output import OutputError, resolve, run_main, write_atomically
from .stages import StageError, bad_argument, run_tool

DEFAULT_PAIRS = "1:2,101:202,11:22"
# A pair's further train drives: seeds train + 1000, train + 2000, ...
TRAIN_SEED_STEP = 1000
# Five train drives' models see each class from more sides than one drive's: 7.0 to 8.0
# points more for each registration method on the four cars at N_thresh 100, three drives 5 to
# 7 (docs/classification.md).
DEFAULT_TRAIN_DRIVES = 5


def parse_pairs(text):
    """[(train seed, test seed), ...] of "1:2,101:202"; ValueError for anything else."""
    pairs = []
    for item in (i for i in text.split(",") if i.strip()):
        seeds = item.split(":")
        if len(seeds) != 2 or not all(s.strip().isdigit() for s in seeds):
            raise ValueError(f"--pairs: '{item}' is not TRAIN_SEED:TEST_SEED")
        train, test = (int(s) for s in seeds)
        if train == test:
            raise ValueError(f"--pairs: '{item}': the test drive must not be the train drive")
        pairs.append((train, test))
    if not pairs:
        raise ValueError("--pairs: at least one TRAIN_SEED:TEST_SEED is needed")
    return pairs


def pair_folder(out, pair):
    return os.path.join(out, f"pair-{pair[0]}-{pair[1]}")


def train_seeds(pair, drives):
    """The seeds of a pair's train drives: its train seed, then + 1000, + 2000, ..."""
    return [pair[0] + TRAIN_SEED_STEP * k for k in range(drives)]


def check_seeds(pairs, drives):
    """ValueError when a test drive's seed is also a train drive's: it would be learnt from."""
    trained = {seed for pair in pairs for seed in train_seeds(pair, drives)}
    for pair in pairs:
        if pair[1] in trained:
            raise ValueError(f"--pairs: test seed {pair[1]} is also a train drive's seed "
                             f"(train drives: each train seed + {TRAIN_SEED_STEP} k, k < "
                             f"{drives}); choose another")


def evaluation_folder(folder, drives):
    return os.path.join(folder, "evaluation" if drives == 1 else f"evaluation-{drives}-drives")


def evaluate_pair(out, pair, duration, args):
    """The pair's bags (simulated when missing) and its evaluation (run when not complete)."""
    folder = pair_folder(out, pair)
    os.makedirs(folder, exist_ok=True)
    drives = [(f"train{'' if k == 0 else f'-{k + 1}'}.bag", seed)
              for k, seed in enumerate(train_seeds(pair, args.train_drives))]
    bags = {}
    for name, seed in drives + [("test.bag", pair[1])]:
        bags[name] = os.path.join(folder, name)
        if args.overwrite or not os.path.exists(bags[name]):
            run_tool(["rosrun", "granular_tools", "simulate_drive", "--out", bags[name],
                      "--duration", str(duration), "--seed", str(seed), "--quiet"],
                     f"simulate_drive (seed {seed})")
    evaluation = evaluation_folder(folder, args.train_drives)
    if not args.overwrite and os.path.exists(os.path.join(evaluation, "report", "summary.json")):
        print(f"evaluate_many: pair {pair[0]}:{pair[1]}: reusing {evaluation}", flush=True)
        return evaluation
    train_bags = ",".join(bags[name] for name, _ in drives)
    command = ["rosrun", "granular_tools", "run_evaluation", "--train-bag", train_bags,
               "--test-bag", bags["test.bag"], "--out", evaluation, "--methods", args.methods,
               "--supervised", args.supervised, "--fitness-from", args.fitness_from,
               "--presets", args.presets,
               "--n-thresh", args.n_thresh, "--overwrite"]
    command += ["--config-dir", args.config_dir] if args.config_dir else []
    run_tool(command, f"run_evaluation (pair {pair[0]}:{pair[1]})")
    return evaluation


def _pooled(correct, votes):
    """The scores of one method, N_thresh and part over the pairs, from each pair's
    instance_groups (per-object and per-track 0/1 lists per instance)."""
    per_pair = [accuracy(groups) for groups in correct]
    per_track = [accuracy(groups) for groups in votes]
    return {
        "pairs": len(per_pair),
        "instances": sum(len(groups) for groups in correct),
        "per_pair": per_pair,
        "mean": sum(per_pair) / len(per_pair),
        "interval": mean_interval(correct),
        "per_track_per_pair": per_track,
        "per_track_mean": sum(per_track) / len(per_track),
        "per_track_interval": mean_interval(votes),
    }


def pooled_summary(evaluations, thresholds):
    """{method: {N<thresh>: {part: scores}}} over the pairs' evaluations: per part (all
    classes, the four cars) the accuracy of each pair, their mean and its interval, and the
    same per track."""
    groups = {}  # (method, N<thresh>, part) -> ([per-object groups], [per-track groups])
    for evaluation in evaluations:
        results_folder = os.path.join(evaluation, "results")
        for method in sorted(os.listdir(results_folder)):
            for threshold in thresholds:
                path = os.path.join(results_folder, method, f"N{threshold}.json")
                if not os.path.exists(path):
                    continue
                results = load_results(path)
                instances = instances_of(os.path.join(evaluation, "test", "objects",
                                                      f"N{threshold}"))
                for part, classes in PARTS:
                    grouped = instance_groups(results["objects"], instances, results["primary"],
                                              classes)
                    if grouped:
                        correct, votes = groups.setdefault((method, f"N{threshold}", part),
                                                           ([], []))
                        correct.append(grouped[0])
                        votes.append(grouped[1])
    summary = {}
    for (method, key, part), (correct, votes) in groups.items():
        summary.setdefault(method, {}).setdefault(key, {})[part] = _pooled(correct, votes)
    return summary


def index_markdown(summary, pairs, duration, drives=1):
    trained = "" if drives == 1 else (
        f"; each pair's models and supervised classifiers learn from {drives} train drives, "
        f"seeds the train seed + {TRAIN_SEED_STEP} k")
    lines = ["# Evaluation over drive pairs", "",
             f"{len(pairs)} independent train/test drive pairs of {duration:g} s (seeds "
             + ", ".join(f"{a}:{b}" for a, b in pairs) + f"{trained}). Accuracy is the mean "
             "over the "
             "pairs (criterion 2 for registration), with a 95 % interval from a bootstrap "
             "over each pair's instances (detection ids); per track, each instance has one "
             "vote. The four cars are " + ", ".join(FOUR_CARS) + ". Each pair's own report: "
             "pair-*/evaluation/report/index.md.", "",
             "| method | N_thresh | instances | accuracy | per track | four-car accuracy "
             "| four cars per track | accuracy per pair |", "|---|---|---|---|---|---|---|---|"]
    for method, by_threshold in sorted(summary.items()):
        for key in sorted(by_threshold, key=lambda k: int(k[1:])):
            entry = by_threshold[key]
            everything, cars = entry.get("all"), entry.get("four_cars")
            if not everything:
                continue
            car_cells = [with_interval(cars["mean"], cars["interval"]),
                         with_interval(cars["per_track_mean"], cars["per_track_interval"])] \
                if cars else ["-", "-"]
            lines.append(" | ".join([
                f"| {method}", key[1:], str(everything["instances"]),
                with_interval(everything["mean"], everything["interval"]),
                with_interval(everything["per_track_mean"], everything["per_track_interval"]),
                *car_cells, ", ".join(f"{a:.3f}" for a in everything["per_pair"])]) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="evaluate_many",
        description="Simulate several independent train/test drive pairs, run the evaluation "
                    "(run_evaluation) on each, and pool them: per method and N_thresh the "
                    "mean accuracy over the pairs with a 95% interval from a bootstrap over "
                    "each pair's vehicle instances, per object and per track, for all classes "
                    "and the four cars (OUT/index.md, OUT/summary.json). A pair already "
                    "evaluated in OUT is reused.")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--pairs", default=DEFAULT_PAIRS, metavar="TRAIN:TEST,...",
                        help="simulator seeds of the train and test drive of each pair "
                             "(default: %(default)s)")
    parser.add_argument("--duration", type=float, default=60.0, metavar="SECONDS",
                        help="length of each drive (default: %(default)s)")
    parser.add_argument("--train-drives", type=int, default=DEFAULT_TRAIN_DRIVES, metavar="K",
                        help="train drives per pair, seeds the train seed + 1000 k for k < K: "
                             "the models and supervised classifiers learn from all of them "
                             "(default: %(default)s)")
    parser.add_argument("--methods", default=",".join(REGISTRATION_METHODS),
                        help="registration methods (default: %(default)s)")
    parser.add_argument("--supervised", default=",".join(DEFAULT_SUPERVISED),
                        help="supervised methods; '' for none (default: %(default)s)")
    parser.add_argument("--fitness-from", default=",".join(DEFAULT_FITNESS_FROM),
                        help="the registrations svm_fitness learns from (default: %(default)s)")
    parser.add_argument("--presets", default="tuned",
                        help="registration presets (default: %(default)s; the report's never "
                             "converges by criterion 2)")
    parser.add_argument("--n-thresh", default="10,100", metavar="N,N,...",
                        help="N_thresh values (default: %(default)s)")
    parser.add_argument("--config-dir", metavar="FOLDER",
                        help="configuration folder for run_evaluation")
    parser.add_argument("--overwrite", action="store_true",
                        help="simulate and evaluate every pair again")
    args = parser.parse_args(argv)
    started = time.monotonic()

    def body():
        try:
            pairs = parse_pairs(args.pairs)
            thresholds = [int(t) for t in args.n_thresh.split(",") if t.strip()]
        except ValueError as error:
            raise bad_argument(str(error)) from error
        if args.duration <= 0 or not thresholds or min(thresholds) < 1 or args.train_drives < 1:
            raise bad_argument("--duration, --train-drives and every --n-thresh must be "
                               "positive")
        try:
            check_seeds(pairs, args.train_drives)
        except ValueError as error:
            raise bad_argument(str(error)) from error
        out = resolve(args.out)
        args.config_dir = resolve(args.config_dir)
        evaluations = []
        for number, pair in enumerate(pairs, 1):
            seeds = ", ".join(map(str, train_seeds(pair, args.train_drives)))
            print(f"evaluate_many: pair {number}/{len(pairs)}: train seed(s) {seeds}, test seed "
                  f"{pair[1]} ({time.monotonic() - started:.0f} s)", flush=True)
            evaluations.append(evaluate_pair(out, pair, args.duration, args))
        try:
            summary = pooled_summary(evaluations, thresholds)
        except ResultsError as error:
            raise StageError("pooling", str(error)) from error
        write_atomically(os.path.join(out, "summary.json"), json.dumps(
            {"pairs": pairs, "duration": args.duration, "train_drives": args.train_drives,
             "methods": summary}, indent=2).encode(), "summary")
        index = index_markdown(summary, pairs, args.duration, args.train_drives)
        write_atomically(os.path.join(out, "index.md"), index.encode(), "index")
        print(index)
        print(f"evaluate_many: done in {time.monotonic() - started:.0f} s: "
              f"{os.path.join(out, 'index.md')}")
        return 0

    return run_main("evaluate_many", body, (StageError, OutputError, OSError))
