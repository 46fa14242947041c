"""Scores over the vehicles behind a test set's objects, not over its objects alone.

A drive holds a few dozen vehicles, each seen in dozens of frames: its objects are a small,
correlated sample. So the 95 % interval of an accuracy comes from a bootstrap over vehicle
instances (detection ids, from the objects folder's index.csv): each resample draws as many
instances as there are, with replacement, and takes the accuracy over all their objects. The
per-track accuracy gives each instance one vote, its most frequent prediction (a tie at the top
counts as wrong: the vote did not decide). The four car classes, which are what tells this
work apart, are scored on their own beside all classes (docs/classification.md).
"""
import csv
import os
from collections import Counter

import numpy as np

from .metrics import ResultsError

FOUR_CARS = ("Sedan", "SUV", "Hatchback", "Jeep")
# The parts a result is scored on: every class (None), and the four cars.
PARTS = (("all", None), ("four_cars", FOUR_CARS))
RESAMPLES = 1000  # bootstrap resamples; the interval's ends move by about 0.002 between seeds
LEVEL = 0.95


def instances_of(objects_folder):
    """{object file name: instance key} from `objects_folder`/index.csv (extract_objects'),
    the key being the label and the detection id."""
    path = os.path.join(objects_folder, "index.csv")
    try:
        with open(path, newline="", encoding="utf-8") as stream:
            return {row["file"]: f"{row['label']}#{row['detection_id']}"
                    for row in csv.DictReader(stream)}
    except (OSError, KeyError, csv.Error) as error:
        raise ResultsError(f"{path}: no objects index with file, label and detection_id "
                           f"({error})") from error


def _resampled_accuracies(correct_per_group, resamples, rng):
    """The pooled accuracy of `resamples` draws of the groups with replacement."""
    hits = np.array([sum(group) for group in correct_per_group], float)
    sizes = np.array([len(group) for group in correct_per_group], float)
    draws = rng.integers(0, len(hits), (resamples, len(hits)))
    return hits[draws].sum(axis=1) / sizes[draws].sum(axis=1)


def _percentiles(values, level):
    tail = (1.0 - level) / 2.0 * 100.0
    low, high = np.percentile(values, [tail, 100.0 - tail])
    return (float(low), float(high))


def bootstrap_interval(correct_per_group, resamples=RESAMPLES, seed=0, level=LEVEL):
    """(low, high): the `level` percentile interval of the pooled accuracy when the groups (a
    list of per-object 0/1 lists, one per instance) are resampled with replacement."""
    return mean_interval([correct_per_group], resamples, seed, level)


def mean_interval(groups_per_run, resamples=RESAMPLES, seed=0, level=LEVEL):
    """(low, high) of the mean over independent runs (drive pairs) of their accuracies, each
    run's instances resampled on their own: `groups_per_run` holds one groups list (as
    bootstrap_interval takes) per run; (0, 0) without any."""
    rng = np.random.default_rng(seed)
    runs = [_resampled_accuracies(groups, resamples, rng) for groups in groups_per_run if groups]
    if not runs:
        return (0.0, 0.0)
    return _percentiles(np.mean(runs, axis=0), level)


def with_interval(value, interval):
    """"0.846 [0.786, 0.898]": an accuracy and its interval, as the reports print them."""
    return f"{value:.3f} [{interval[0]:.3f}, {interval[1]:.3f}]"


def track_vote(true_label, predictions):
    """Whether an instance's vote (its most frequent prediction; None is a prediction of
    nothing) is its true label; a tie at the top is no decision, so wrong."""
    counts = Counter(predictions).most_common()
    top = [label for label, count in counts if count == counts[0][1]]
    return len(top) == 1 and top[0] == true_label


def instance_groups(records, instances, primary, classes=None):
    """(correct, votes) of the results `records` whose true label is in `classes` (all when
    None): per instance, the 0/1 of its objects, and the 0/1 of its track's vote (a one-item
    list); None when there are none. `instances` maps an object's file name to its instance;
    an object missing from it is a ResultsError."""
    groups = {}
    for record in records:
        if classes is not None and record["true_label"] not in classes:
            continue
        name = os.path.basename(record["file"])
        if name not in instances:
            raise ResultsError(f"{name}: not in the objects index")
        groups.setdefault(instances[name], []).append(record)
    if not groups:
        return None
    correct = [[r["predictions"].get(primary) == r["true_label"] for r in group]
               for group in groups.values()]
    votes = [[track_vote(group[0]["true_label"],
                         [r["predictions"].get(primary) for r in group])]
             for group in groups.values()]
    return correct, votes


def accuracy(groups):
    return sum(map(sum, groups)) / sum(map(len, groups))


def instance_scores(records, instances, primary, classes=None, resamples=RESAMPLES, seed=0):
    """Accuracy with its interval over instances, and the per-track accuracy with its own
    (tracks resampled), as instance_groups selects them; None when there are none."""
    grouped = instance_groups(records, instances, primary, classes)
    if grouped is None:
        return None
    correct, votes = grouped
    return {
        "instances": len(correct),
        "objects": sum(map(len, correct)),
        "accuracy": accuracy(correct),
        "interval": bootstrap_interval(correct, resamples, seed),
        "per_track": accuracy(votes),
        "per_track_interval": bootstrap_interval(votes, resamples, seed),
    }
