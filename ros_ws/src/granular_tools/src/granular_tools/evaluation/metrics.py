"""Scores of one method on one test set, from its results file.

A results file (written by the classify tools) holds one record per object with its
`true_label` and `predictions`, a dict of named predictions (the registration methods' three
criteria, or a supervised classifier's single label); a prediction may be null (missing).
The file's `primary` names the prediction the report ranks by (criterion 2 by default, as the
report does). Accuracy counts a missing prediction as wrong; `coverage` says how many objects
got one.
"""
import json

import numpy as np
from sklearn.metrics import confusion_matrix, precision_recall_fscore_support

MISSING = "(none)"


class ResultsError(ValueError):
    """A results file that cannot be scored; the message names the file."""


def load_results(path):
    try:
        with open(path, encoding="utf-8") as stream:
            results = json.load(stream)
        objects = results["objects"]
        for record in objects:
            record["true_label"], record["predictions"]  # noqa: B018 - presence check
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise ResultsError(f"{path}: not a classification results file ({error})") from error
    names = sorted({name for record in objects for name in record["predictions"]})
    results.setdefault("primary", "criterion2" if "criterion2" in names else
                       (names[0] if names else "label"))
    return results


def score(true_labels, predicted, classes):
    """Accuracy, macro F1 and per-class precision/recall/support; None counts as wrong."""
    true_labels = list(true_labels)
    predicted = [MISSING if p is None else p for p in predicted]
    total = len(true_labels)
    correct = sum(t == p for t, p in zip(true_labels, predicted))
    precision, recall, f1, support = precision_recall_fscore_support(
        true_labels, predicted, labels=classes, zero_division=0)
    present = [k for k, c in enumerate(classes) if support[k] > 0]
    return {
        "objects": total,
        "accuracy": correct / total if total else 0.0,
        "coverage": sum(p != MISSING for p in predicted) / total if total else 0.0,
        "macro_f1": float(np.mean(f1[present])) if present else 0.0,
        "per_class": {c: {"precision": float(precision[k]), "recall": float(recall[k]),
                          "support": int(support[k])} for k, c in enumerate(classes)},
    }


def confusion(true_labels, predicted, classes):
    """Counts, rows = true class, columns = predicted class plus a last column for missing."""
    predicted = [MISSING if p is None else p for p in predicted]
    return confusion_matrix(list(true_labels), predicted, labels=list(classes) + [MISSING])[
        :len(classes)]


def summarise(results, classes):
    """The summary.json entry of one results file."""
    objects = results["objects"]
    truth = [r["true_label"] for r in objects]
    names = sorted({name for r in objects for name in r["predictions"]})
    entry = score(truth, [r["predictions"].get(results["primary"]) for r in objects], classes)
    entry["primary"] = results["primary"]
    entry["missing"] = {n: sum(r["predictions"].get(n) is None for r in objects) for n in names}
    entry["by_prediction"] = {
        n: {k: v for k, v in score(truth, [r["predictions"].get(n) for r in objects],
                                   classes).items() if k in ("accuracy", "coverage", "macro_f1")}
        for n in names}
    for key in ("seconds", "seconds_to_train", "microseconds_per_object"):
        if key in results:
            entry[key] = results[key]
    return entry
