"""make_report: summary.json, confusion matrices, precision/recall plots and index.md.

Reads RESULTS/<method>/N<thresh>.json (one results file per method and test set) and writes
OUT/summary.json, OUT/confusion/<method>-N<thresh>.png, OUT/precision_recall/<method>.png,
OUT/accuracy.png and OUT/index.md, which puts them together with the model pictures. Given the
test objects (OBJECTS/N<thresh>/index.csv), the accuracies get 95 % intervals over instances
(vehicles and pedestrians) and per-track accuracies beside them (instances.py).
"""
import argparse
import json
import multiprocessing
import os
import pathlib
import re
import signal

import matplotlib

matplotlib.use("Agg")  # Files only: no display needed.
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..labels import object_label  # noqa: E402
from ..output import OutputFolder, run_main, save_figure, write_file  # noqa: E402
from ..pcd import CloudError, read_pcd  # noqa: E402
from .instances import (FOUR_CARS, PARTS, instance_scores, instances_of,  # noqa: E402
                        with_interval)
from .metrics import MISSING, ResultsError, confusion, load_results, summarise  # noqa: E402

RESULTS_NAME = re.compile(r"^N(\d+)\.json$")
# The report's classes first, in its order; any others follow alphabetically.
PREFERRED_ORDER = ["Sedan", "Hatchback", "SUV", "Jeep", "BoxTruck", "SchoolBus", "Pedestrian"]


def discover(results_folder):
    """{method: {threshold: path}} for every RESULTS/<method>/N<thresh>.json."""
    found = {}
    for method_folder in sorted(pathlib.Path(results_folder).iterdir()):
        if not method_folder.is_dir():
            continue
        for path in method_folder.iterdir():
            match = RESULTS_NAME.match(path.name)
            if match:
                found.setdefault(method_folder.name, {})[int(match.group(1))] = path
    if not found:
        raise ResultsError(f"{results_folder}: no <method>/N<thresh>.json results")
    return found


def ordered_classes(labels):
    return [c for c in PREFERRED_ORDER if c in labels] + sorted(set(labels) - set(PREFERRED_ORDER))


def plot_confusion(counts, classes, title, path):
    has_missing = counts[:, -1].sum() > 0
    shown = counts if has_missing else counts[:, :-1]
    columns = classes + ([MISSING] if has_missing else [])
    rows = shown.sum(axis=1, keepdims=True)
    normalised = np.divide(shown, rows, out=np.zeros(shown.shape), where=rows > 0)
    figure, ax = plt.subplots(figsize=(1.1 * len(columns) + 2.5, 0.9 * len(classes) + 1.8))
    ax.imshow(normalised, cmap="Blues", vmin=0.0, vmax=1.0)
    for i in range(len(classes)):
        for j in range(len(columns)):
            ax.text(j, i, f"{normalised[i, j]:.2f}\n{shown[i, j]}", ha="center", va="center",
                    fontsize=8, color="white" if normalised[i, j] > 0.6 else "black")
    ax.set_xticks(range(len(columns)), columns, rotation=35, ha="right", fontsize=8)
    ax.set_yticks(range(len(classes)), [f"{c} ({int(rows[i, 0])})" for i, c in
                                        enumerate(classes)], fontsize=8)
    ax.set_xlabel("predicted")
    ax.set_ylabel("true (objects)")
    ax.set_title(title, fontsize=10)
    figure.tight_layout()
    save_figure(figure, path)
    plt.close(figure)


def plot_precision_recall(method, by_threshold, classes, path):
    thresholds = sorted(by_threshold)
    columns = min(4, len(classes))
    rows = -(-len(classes) // columns)
    figure, axes = plt.subplots(rows, columns, figsize=(3.0 * columns, 2.6 * rows + 0.4),
                                sharey=True, squeeze=False)
    for ax in axes.flat[len(classes):]:
        ax.set_visible(False)
    for ax, label in zip(axes.flat, classes):
        for metric, style in (("precision", "o-"), ("recall", "s--")):
            ax.plot(thresholds, [by_threshold[t]["per_class"][label][metric] for t in thresholds],
                    style, label=metric)
        ax.set_title(label, fontsize=9)
        ax.set_xscale("log")
        ax.set_xticks(thresholds, [str(t) for t in thresholds], fontsize=7)
        ax.set_xlabel("N_thresh", fontsize=8)
        ax.set_ylim(-0.02, 1.02)
    axes.flat[0].legend(fontsize=7)
    figure.suptitle(f"{method}: precision and recall per class against N_thresh", fontsize=10)
    figure.tight_layout()
    save_figure(figure, path)
    plt.close(figure)


def plot_accuracy(summary, path):
    figure, ax = plt.subplots(figsize=(6.5, 3.8))
    for method, by_threshold in sorted(summary.items()):
        thresholds = sorted(by_threshold, key=lambda k: int(k[1:]))
        accuracies = [by_threshold[t]["accuracy"] for t in thresholds]
        intervals = [by_threshold[t].get("instances", {}).get("all") for t in thresholds]
        errors = None
        if all(intervals):  # the 95 % interval over instances
            errors = np.array([[a - i["interval"][0], i["interval"][1] - a]
                               for a, i in zip(accuracies, intervals)]).T.clip(min=0.0)
        ax.errorbar([int(t[1:]) for t in thresholds], accuracies, yerr=errors, fmt="o-",
                    capsize=3, label=method)
    ax.set_xscale("log")
    ax.set_xlabel("N_thresh (minimum points per object)")
    with_intervals = any("instances" in entry for by_threshold in summary.values()
                         for entry in by_threshold.values())
    ax.set_ylabel("accuracy (bars: 95 % over instances)" if with_intervals else "accuracy")
    ax.set_ylim(0.0, 1.02)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    figure.tight_layout()
    save_figure(figure, path)
    plt.close(figure)


def _criteria_cells(entry):
    """'accuracy (missing)' of criteria 1, 2 and 3 of a registration entry; '-' otherwise."""
    cells = []
    for name in ("criterion1", "criterion2", "criterion3"):
        scores = entry["by_prediction"].get(name)
        cells.append(f"{scores['accuracy']:.3f} ({entry['missing'][name]})" if scores else "-")
    return cells


def plot_feature_distributions(objects_folder, classes, path):
    """Box plots of [mean, std] of x, y, z per class over an objects folder's PCDs."""
    values = {}
    for pcd in sorted(pathlib.Path(objects_folder).glob("*.pcd")):
        label = object_label(pcd)
        if label is None:
            continue
        _, points, _, _ = read_pcd(str(pcd))
        xyz = np.stack([points[a] for a in "xyz"], axis=1).astype(float)
        xyz = xyz[np.all(np.isfinite(xyz), axis=1)]
        if len(xyz):
            values.setdefault(label, []).append(np.concatenate([xyz.mean(0), xyz.std(0)]))
    shown = [c for c in classes if c in values] + sorted(set(values) - set(classes))
    if not shown:
        raise ResultsError(f"{objects_folder}: no object PCDs for the feature picture")
    names = ["mean x", "mean y", "mean z", "std x", "std y", "std z"]
    figure, axes = plt.subplots(2, 3, figsize=(12, 6.5))
    for k, ax in enumerate(axes.flat):
        ax.boxplot([np.array(values[c])[:, k] for c in shown], showfliers=False)
        ax.set_xticks(range(1, len(shown) + 1), shown, rotation=35, ha="right", fontsize=7)
        ax.set_title(f"{names[k]} (m)", fontsize=9)
    figure.suptitle("kNN features of the training objects per class", fontsize=10)
    figure.tight_layout()
    save_figure(figure, path)
    plt.close(figure)


def _instances_table(summary):
    """index.md's table of accuracies over instances; none without them."""
    rows = []
    for method, by_threshold in sorted(summary.items()):
        for key in sorted(by_threshold, key=lambda k: int(k[1:])):
            instances = by_threshold[key].get("instances")
            if not instances:
                continue
            cells = []
            for part in ("all", "four_cars"):
                scores = instances.get(part)
                cells += [str(scores["instances"]), with_interval(scores["accuracy"],
                                                                    scores["interval"]),
                          with_interval(scores["per_track"], scores["per_track_interval"])] \
                    if scores else ["-", "-", "-"]
            rows.append(f"| {method} | {key[1:]} | " + " | ".join(cells) + " |")
    if not rows:
        return []
    return ["", "## Over instances", "",
            "A drive's objects are a few dozen vehicles and pedestrians (instances) seen in "
            "many frames each. The brackets are 95 % intervals from a bootstrap over instances "
            "(detection ids), not over objects; per track, each instance has one vote, its "
            "most frequent prediction (a tie is wrong). The four cars are "
            + ", ".join(FOUR_CARS) + ".", "",
            "| method | N_thresh | instances | accuracy | per track | car instances "
            "| four-car accuracy | four-car per track |",
            "|---|---|---|---|---|---|---|---|"] + rows


def _left_out_lines(models_json):
    """index.md's list of the classes build_models left out (too little data), from the models
    folder's models.json; none when it left none out or is not there."""
    try:
        with open(models_json, encoding="utf-8") as stream:
            left_out = json.load(stream).get("left_out") or {}
    except (OSError, ValueError):
        return []
    if not left_out:
        return []
    return ["", "Left out, with too little data for a model (no method was trained on or "
                "answers them):", ""] + [f"- {label}: {why}"
                                         for label, why in sorted(left_out.items())]


def write_index(out, summary, classes, model_pictures):
    lines = ["# Classification report", "",
             "Accuracy counts a missing prediction as wrong; coverage is the share of objects "
             "with a prediction. Registration methods are ranked by criterion 2 (the report's "
             "choice); the criteria columns give each criterion's accuracy and, in brackets, "
             "the objects it leaves without a prediction. Seconds: the whole test set (for "
             "registration, models prepared and every object registered against every model); "
             "supervised classifiers also give their training time and the microseconds per "
             "object (features and prediction, one core).", "",
             "![accuracy against N_thresh](accuracy.png)", "",
             "| method | N_thresh | objects | accuracy | macro F1 | coverage | criterion 1 "
             "| criterion 2 | criterion 3 | seconds | seconds to train | us per object |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for method, by_threshold in sorted(summary.items()):
        for key in sorted(by_threshold, key=lambda k: int(k[1:])):
            entry = by_threshold[key]
            seconds, train, per_object = (
                f"{entry[k]:{f}}" if k in entry else "" for k, f in
                (("seconds", ".2f"), ("seconds_to_train", ".2f"),
                 ("microseconds_per_object", ".0f")))
            criteria = " | ".join(_criteria_cells(entry))
            lines.append(f"| {method} | {key[1:]} | {entry['objects']} | {entry['accuracy']:.3f} "
                         f"| {entry['macro_f1']:.3f} | {entry['coverage']:.3f} | {criteria} "
                         f"| {seconds} | {train} | {per_object} |")
    lines += _instances_table(summary)
    for method, by_threshold in sorted(summary.items()):
        lines += ["", f"## {method}", "", f"![precision and recall]"
                  f"(precision_recall/{method}.png)", ""]
        for key in sorted(by_threshold, key=lambda k: int(k[1:])):
            lines.append(f"![{method} {key}](confusion/{method}-{key}.png)")
    if (pathlib.Path(out) / "features.png").exists():
        lines += ["", "## Feature space", "",
                  "The kNN's features over the training objects, per class (the report's "
                  "figures 19-22):", "", "![mean and standard deviation per class](features.png)"]
    if model_pictures:
        overview = pathlib.Path(model_pictures) / "overview.png"
        if overview.exists():
            relative = os.path.relpath(overview, out)
            lines += ["", "## Class models", "", f"![class models]({relative})"]
        lines += _left_out_lines(pathlib.Path(model_pictures).parent / "models.json")
    write_file(os.path.join(out, "index.md"), ("\n".join(lines) + "\n").encode(), "index")


def scores_over_instances(result, objects_folder):
    """summary.json's "instances" of a results file: instance_scores over all classes and over
    the four cars (None without any)."""
    instances = instances_of(objects_folder)
    return {part: instance_scores(result["objects"], instances, result["primary"], classes)
            for part, classes in PARTS}


def _draw(picture):
    function, arguments = picture
    function(*arguments)


def _worker_signals():
    """A worker dies at once on a stop signal. Forked, it would inherit the tool's handlers
    (output.stop_on_signals), which raise inside the pool's own locks: a worker stopped that way
    hung on a lock for good, and the tool with it, waiting to join it."""
    for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(signum, signal.SIG_DFL)


def draw_pictures(pictures):
    """Draw each (function, arguments) picture, in worker processes on every core: matplotlib
    spends most of a report's time laying out tick labels (the demo's 55 pictures took 27 s on
    one core)."""
    workers = min(len(pictures), os.cpu_count() or 1)
    if workers <= 1:
        for picture in pictures:
            _draw(picture)
        return
    pool = multiprocessing.get_context("fork").Pool(workers, initializer=_worker_signals)
    try:
        pool.map(_draw, pictures, chunksize=1)
        pool.close()  # the workers finish and exit; terminate() only on an error or a stop
    except BaseException:
        pool.terminate()
        raise
    finally:
        pool.join()


def make_report(results_folder, out, model_pictures=None, feature_objects=None, objects=None,
                overwrite=False):
    """Write the report into `out`, built in a sibling folder and renamed into place; with
    `overwrite`, replacing a report there. `objects`: the test objects folder
    (N<thresh>/index.csv), for the scores over instances."""
    found = discover(results_folder)
    results = {m: {t: load_results(p) for t, p in by_t.items()} for m, by_t in found.items()}
    classes = ordered_classes({r["true_label"] for by_t in results.values()
                               for res in by_t.values() for r in res["objects"]})
    # A report replaces only a report, and only when asked; never a folder of other files.
    with OutputFolder(out, "make_report", overwrite=overwrite,
                      inputs=(results_folder, model_pictures, feature_objects, objects)) as folder:
        staging = folder.staging
        os.makedirs(os.path.join(staging, "confusion"))
        os.makedirs(os.path.join(staging, "precision_recall"))
        summary = {}
        pictures = []  # (plotting function, its arguments)
        for method, by_threshold in sorted(results.items()):
            summary[method] = {}
            for threshold, result in sorted(by_threshold.items()):
                key = f"N{threshold}"
                summary[method][key] = summarise(result, classes)
                if objects:
                    summary[method][key]["instances"] = scores_over_instances(
                        result, os.path.join(objects, key))
                truth = [r["true_label"] for r in result["objects"]]
                predicted = [r["predictions"].get(result["primary"]) for r in result["objects"]]
                pictures.append((plot_confusion, (
                    confusion(truth, predicted, classes), classes,
                    f"{method}, N_thresh {threshold} ({result['primary']})",
                    os.path.join(staging, "confusion", f"{method}-{key}.png"))))
            pictures.append((plot_precision_recall, (
                method, {int(k[1:]): v for k, v in summary[method].items()}, classes,
                os.path.join(staging, "precision_recall", f"{method}.png"))))
        pictures.append((plot_accuracy, (summary, os.path.join(staging, "accuracy.png"))))
        if feature_objects:
            pictures.append((plot_feature_distributions, (
                feature_objects, classes, os.path.join(staging, "features.png"))))
        draw_pictures(pictures)
        write_file(os.path.join(staging, "summary.json"),
                   json.dumps({"classes": classes, "methods": summary}, indent=2).encode(),
                   "summary")
        write_index(staging, summary, classes, model_pictures)
        folder.commit()
    return summary


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="make_report",
        description="Score classification results (RESULTS/<method>/N<thresh>.json) and write "
                    "OUT/summary.json, confusion matrices, precision/recall against N_thresh, "
                    "an accuracy plot and OUT/index.md.")
    parser.add_argument("--results", required=True, help="folder of <method>/N<thresh>.json")
    parser.add_argument("--out", required=True, help="report folder (created)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace --out when it holds a report make_report wrote")
    parser.add_argument("--model-pictures", metavar="FOLDER",
                        help="render_models output to show in index.md")
    parser.add_argument("--objects", metavar="FOLDER",
                        help="the test objects folder (N<thresh>/index.csv, extract_objects'): "
                             "95%% intervals over instances (detection ids) and per-track accuracy")
    parser.add_argument("--feature-objects", metavar="FOLDER",
                        help="training objects folder whose kNN features (mean and std of x, "
                             "y, z) to picture per class")
    args = parser.parse_args(argv)

    def body():
        summary = make_report(args.results, args.out, args.model_pictures, args.feature_objects,
                              args.objects, args.overwrite)
        for method, by_threshold in sorted(summary.items()):
            cells = ", ".join(f"{k} {v['accuracy']:.3f}" for k, v in
                              sorted(by_threshold.items(), key=lambda kv: int(kv[0][1:])))
            print(f"make_report: {method}: accuracy {cells}")
        print(f"make_report: {os.path.join(args.out, 'index.md')}")
        return 0

    return run_main("make_report", body, (ResultsError, CloudError, OSError))
