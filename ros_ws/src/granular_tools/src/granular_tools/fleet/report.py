"""The fleet's report: every classified bag's results as one test set (OUT/fleet_results), the
evaluation's report over it (make_report: confusion matrices, per-class precision and recall,
accuracy with the bootstrap over instances, OUT/report), and OUT/index.md with each bag's
status and accuracy.

Object file names and detection ids repeat from drive to drive, so the merged records are
named <bag>--<file> and the merged index's instances <bag>:<detection id>: a vehicle of one
drive is one instance, never pooled with another drive's vehicle of the same id.
"""
import csv
import json
import os

from ..evaluation import report as evaluation_report
from ..evaluation.instances import with_interval
from ..evaluation.metrics import ResultsError, load_results
from ..output import OutputFolder, write_atomically

SEPARATOR = "--"


def bag_accuracy(results):
    """The share of a results file's objects whose primary prediction is their label."""
    objects = results["objects"]
    return (sum(r["predictions"].get(results["primary"]) == r["true_label"] for r in objects)
            / len(objects)) if objects else None


def predicted_counts(results):
    counts = {}
    for record in results["objects"]:
        label = record["predictions"].get(results["primary"]) or "(none)"
        counts[label] = counts.get(label, 0) + 1
    return counts


def merge(config, folders, target):
    """{results name: {N<t>: {bag: accuracy or predicted counts}}} of the bags' results files,
    written as one test set into `target` (results/<name>/N<t>.json, objects/N<t>/index.csv),
    each record cut to what the report reads."""
    per_bag = {}
    with OutputFolder(target, "run_fleet", overwrite=True) as folder:
        for threshold in config.thresholds:
            key = f"N{threshold}"
            index_folder = os.path.join(folder.staging, "objects", key)
            os.makedirs(index_folder)
            with open(os.path.join(index_folder, "index.csv"), "w", newline="",
                      encoding="utf-8") as stream:
                writer = None
                for bag_id, bag_folder in folders.items():
                    with open(os.path.join(bag_folder, "objects", key, "index.csv"), newline="",
                              encoding="utf-8") as source:
                        for row in csv.DictReader(source):
                            if writer is None:
                                writer = csv.DictWriter(stream, list(row), lineterminator="\n")
                                writer.writeheader()
                            row["file"] = f"{bag_id}{SEPARATOR}{row['file']}"
                            row["detection_id"] = f"{bag_id}:{row['detection_id']}"
                            writer.writerow(row)
            for name in config.result_names:
                merged = None
                for bag_id, bag_folder in folders.items():
                    results = load_results(os.path.join(bag_folder, "results", name,
                                                        f"{key}.json"))
                    scores = per_bag.setdefault(name, {}).setdefault(key, {})
                    scores[bag_id] = (predicted_counts(results) if config.boxes == "segment"
                                      else bag_accuracy(results))
                    records = [{"file": f"{bag_id}{SEPARATOR}{os.path.basename(r['file'])}",
                                "true_label": r["true_label"], "predictions": r["predictions"]}
                               for r in results["objects"]]
                    if merged is None:
                        merged = {"primary": results["primary"], "objects": [], "seconds": 0.0,
                                  "bags": []}
                    merged["objects"] += records
                    merged["seconds"] += results.get("seconds", 0.0)
                    merged["bags"].append(bag_id)
                os.makedirs(os.path.join(folder.staging, "results", name), exist_ok=True)
                with open(os.path.join(folder.staging, "results", name, f"{key}.json"), "w",
                          encoding="utf-8") as stream:
                    json.dump(merged, stream)
        folder.commit()
    return per_bag


def _bag_rows(config, ledger, ids, per_bag):
    keys = [f"N{t}" for t in config.thresholds]
    header = ["bag", "role", "status", "drive (s)"] + [f"objects {k}" for k in keys]
    if config.boxes == "detections":
        header += [f"{name} {k}" for name in config.result_names for k in keys]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for bag_id in sorted(ids):
        entry = ledger.data["bags"][bag_id]
        objects = entry.get("objects", {})
        drive = entry.get("drive_seconds")
        cells = [bag_id, entry.get("role", ""), entry.get("status", ""),
                 f"{drive:.1f}" if drive is not None else ""]
        cells += [str(objects.get(k, "")) if entry.get("role") != "train" else "" for k in keys]
        if config.boxes == "detections":
            for name in config.result_names:
                for k in keys:
                    value = per_bag.get(name, {}).get(k, {}).get(bag_id)
                    cells.append(f"{value:.3f}" if value is not None else "")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def _fleet_rows(summary):
    lines = ["| method | N_thresh | objects | accuracy [95 % over instances] | per track |",
             "|---|---|---|---|---|"]
    for method, by_threshold in sorted(summary.items()):
        for key in sorted(by_threshold, key=lambda k: int(k[1:])):
            entry = by_threshold[key]
            scores = (entry.get("instances") or {}).get("all")
            lines.append(f"| {method} | {key[1:]} | {entry['objects']} | "
                         + (f"{with_interval(entry['accuracy'], scores['interval'])} | "
                            f"{with_interval(scores['per_track'], scores['per_track_interval'])}"
                            if scores else f"{entry['accuracy']:.3f} | -") + " |")
    return lines


def _prediction_rows(per_bag):
    lines = ["| method | N_thresh | predicted classes over the fleet (objects) |", "|---|---|---|"]
    for name, by_threshold in sorted(per_bag.items()):
        for key, by_bag in sorted(by_threshold.items(), key=lambda kv: int(kv[0][1:])):
            total = {}
            for counts in by_bag.values():
                for label, count in counts.items():
                    total[label] = total.get(label, 0) + count
            lines.append(f"| {name} | {key[1:]} | "
                         + ", ".join(f"{label} {count}" for label, count in sorted(total.items()))
                         + " |")
    return lines


def write(config, ledger, ids):
    """The fleet's report; returns the path of OUT/index.md. ids: {bag path: bag id}."""
    bag_ids = sorted(ids.values())
    entries = ledger.data["bags"]
    classified = {b: config.folder("bags", b) for b in bag_ids
                  if entries[b].get("role") != "train" and entries[b].get("status") != "failed"}
    per_bag, summary = {}, None
    lines = ["# Fleet report", ""]
    if classified:
        per_bag = merge(config, classified, config.folder("fleet_results"))
        if config.boxes == "detections":
            try:
                summary = evaluation_report.make_report(
                    config.folder("fleet_results", "results"), config.folder("report"),
                    objects=config.folder("fleet_results", "objects"), overwrite=True)
            except ResultsError as error:
                lines += [f"The report over the fleet failed: {error}", ""]
    counts = {s: sum(entries[b].get("status") == s for b in bag_ids)
              for s in ("done", "skipped", "failed")}
    drive = sum(entries[b].get("drive_seconds") or 0.0 for b in classified)
    lines += [f"{len(bag_ids)} bags: {counts['done']} done, {counts['skipped']} skipped (done by "
              f"an earlier run with the same bag and configuration), {counts['failed']} failed. "
              f"Classified: {len(classified)} bags, {drive / 3600.0:.2f} hours of drive "
              f"({drive:.0f} s). "
              f"Models: {ledger.data['models'].get('status', 'not built')} "
              f"(objects per class: " + ", ".join(
                  f"{c} {n}" for c, n in sorted(ledger.data['models'].get('classes', {})
                                                .items())) + ").", ""]
    if summary:
        lines += ["## Over the fleet", "",
                  "Accuracy of each method's primary prediction over every classified bag's "
                  "objects; the interval is a bootstrap over instances (one drive's vehicle is "
                  "one instance). Confusion matrices and per-class precision and recall: "
                  "[report/index.md](report/index.md).", ""] + _fleet_rows(summary) + [""]
    elif per_bag:
        lines += ["## Over the fleet", "",
                  "The box-free path's objects have no true class: what each method predicts.",
                  ""] + _prediction_rows(per_bag) + [""]
    lines += ["## Bags", ""] + _bag_rows(config, ledger, bag_ids, per_bag)
    failed = [b for b in bag_ids if entries[b].get("status") == "failed"]
    if failed:
        lines += ["", "## Failed bags", ""] + [f"- {b} ({entries[b].get('bag')}): "
                                               f"{entries[b].get('message')}" for b in failed]
    for bag_id in bag_ids:
        for name, by_threshold in per_bag.items():
            for key, by_bag in by_threshold.items():
                if bag_id in by_bag:
                    entries[bag_id].setdefault("accuracy" if config.boxes == "detections"
                                               else "predicted", {}).setdefault(
                        name, {})[key] = by_bag[bag_id]
    ledger.save()
    index = config.folder("index.md")
    write_atomically(index, ("\n".join(lines) + "\n").encode(), "fleet index")
    return index
