"""evaluate_cuboids: predicted cuboids against true ones, frame by frame (docs/cuboids.md).

Both sides are folders of <stamp>.json in the layout of a frames folder's detections_3d/ (a
frames folder is taken for its detections_3d/, and its pcd/ gives the clouds for
--min-points). Per frame, predictions are matched one-to-one to truths by a Hungarian
assignment on the x-y centre distance, gated; the same pairs are then scored under every
criterion, class-agnostic and class-aware (the class map says which predicted labels count as
which true labels). Truths outside the filters are "don't care": they are not missed, and a
prediction that goes to one is not a false positive.

Writes OUT/summary.json, OUT/index.md and histograms of the matched pairs' errors.
"""
import argparse
import json
import math
import os

import numpy as np

from .. import progress
from ..frames_folder import DetectionsError
from ..output import (OutputError, OutputFolder, check_output_apart, run_main, save_figure,
                      write_file)
from ..pcd import CloudError
from .cuboid_matching import (CENTRE_TOLERANCE_M, CRITERIA, CRITERION_TITLES, DEFAULT_CLASS_MAP,
                              ERROR_KEYS, GATE_M, TOOL, YAW_TOLERANCE_DEG, CuboidError, Filters,
                              Settings, UsageError, evaluate, load_class_map)


def _cell(value, digits=3):
    return "-" if value is None else f"{value:.{digits}f}"


def unclassified(overall):
    """Whether every counted prediction is labelled unknown (no classifier named it): the
    class-aware figures then score nothing, and are shown as '-'."""
    return overall["predictions"] > 0 and \
        overall["unclassified_predictions"] == overall["predictions"]


UNCLASSIFIED_NOTE = "not scored, every prediction is unknown (no classifier named it)"


def criteria_table(overall):
    lines = ["| criterion | TP | FP | FN | precision | recall | F1 | class-aware TP "
             "| class-aware precision | class-aware recall | class-aware F1 |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    classless = unclassified(overall)
    for name in CRITERIA:
        s, c = overall["criteria"][name], overall["class_aware"][name]
        if classless:
            c = {"tp": "-", "precision": None, "recall": None, "f1": None}
        lines.append(f"| {CRITERION_TITLES[name]} | {s['tp']} | {s['fp']} | {s['fn']} "
                     f"| {_cell(s['precision'])} | {_cell(s['recall'])} | {_cell(s['f1'])} "
                     f"| {c['tp']} | {_cell(c['precision'])} | {_cell(c['recall'])} "
                     f"| {_cell(c['f1'])} |")
    if classless:
        lines += ["", f"Class-aware: {UNCLASSIFIED_NOTE}."]
    return lines


ERROR_TITLES = {"centre_3d_m": "centre, 3-D (m)", "centre_xy_m": "centre, x-y (m)",
                "yaw_deg": "yaw, modulo 180 (degrees)", "length_m": "length, absolute (m)",
                "width_m": "width, absolute (m)", "height_m": "height, absolute (m)",
                "bev_iou": "bird's-eye IoU", "iou_3d": "3-D IoU"}


def tracking_lines(tracking):
    settle = tracking["frames_to_settle"]
    return [
        "## Tracking", "",
        "The predicted ids are tracks, the true ids vehicles. A frame's pairs above that pass "
        "the paper's criterion are its correspondences; a vehicle followed by another track "
        "than the one that last followed it is an identity switch (IDSW). MOTA = 1 - (FN + FP "
        "+ IDSW) / truths; switches per 100 track-frames = 100 IDSW / TP. A track settles on "
        "its class in the frame (1: its first following a vehicle) from which its label counts "
        "as the true label of the vehicle it followed most, to its last frame. Class-aware F1 "
        "per track: the paper's criterion's class-aware F1 with each track named in every "
        "frame by its final class (its label in its last frame, the vote over all its "
        "frames).", "",
        "| MOTA | TP | FP | FN | IDSW | IDSW per 100 track-frames | vehicles | tracks "
        "| class-aware F1 per track | tracks settled | frames to settle: median | mean | p90 |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        f"| {_cell(tracking['mota'])} | {tracking['tp']} | {tracking['fp']} | {tracking['fn']} "
        f"| {tracking['id_switches']} | {_cell(tracking['id_switches_per_100_track_frames'], 2)} "
        f"| {tracking['vehicles_followed']} | {tracking['tracks_following']} "
        f"| {_cell(tracking['class_aware_f1_per_track'])} | {tracking['class_settled_tracks']} | {_cell(settle['median'], 1)} "
        f"| {_cell(settle['mean'], 1)} | {_cell(settle['p90'], 1)} |"]


def write_index(path, summary):
    overall, settings, frames = summary["overall"], summary["settings"], summary["frames"]
    filters = [f"true centre within {settings['max_range_m']:g} m (x-y) of the sensor"
               if settings["max_range_m"] is not None else None,
               f"true centre within {settings['field_of_view_deg']:g} degrees of straight ahead"
               if settings.get("field_of_view_deg") is not None else None,
               f"at least {settings['min_points']} points inside the true box"
               if settings["min_points"] is not None else None,
               f"true labels {', '.join(settings['labels'])}" if settings["labels"] else None]
    filters = [f for f in filters if f]
    mapped = ", ".join(f"{p} as {'/'.join(t)}" for p, t in settings["class_map"].items())
    lines = [
        "# Cuboid evaluation", "",
        f"Truth `{summary['truth']}`, predictions `{summary['predicted']}`: "
        f"{frames['truth']} frames, {len(frames['without_predictions'])} of them without a "
        f"predictions file (scored as frames with no predictions); "
        f"{len(frames['only_predicted_ignored'])} predictions files without truth, ignored.", "",
        f"{overall['truths']} truths evaluated ({overall['truths_ignored']} don't care), "
        f"{overall['predictions']} predictions counted ({overall['predictions_ignored']} "
        f"ignored: matched to a don't-care truth or beyond the range), {overall['matched']} "
        f"matched pairs (Hungarian on the x-y centre distance, gate {settings['gate_m']:g} m; "
        "the same pairs for every criterion). Filters: "
        + ("; ".join(filters) if filters else "none") + ". Class map "
        f"({settings['class_map_source']}): every label counts as itself"
        + (f"; {mapped}" if mapped else "") + ".", "",
        "A matched pair that passes a criterion is a true positive; precision = TP / "
        "predictions, recall = TP / truths, F1 = 2 TP / (2 TP + FP + FN); class-aware also "
        "needs the predicted label to count as the true one.", "",
    ] + criteria_table(overall) + [
        "", "## Errors of the matched pairs", "",
        "| error | pairs | median | mean | p90 |", "|---|---|---|---|---|"]
    for key in ERROR_KEYS:
        d = overall["errors"][key]
        lines.append(f"| {ERROR_TITLES[key]} | {d['count']} | {_cell(d['median'])} "
                     f"| {_cell(d['mean'])} | {_cell(d['p90'])} |")
    if overall["per_true_label"]:
        lines += ["", "## Recall per true label", "",
                  "| label | truths | matched | " + " | ".join(CRITERION_TITLES.values())
                  + " |", "|---|---|---|" + "---|" * len(CRITERIA)]
        for label, e in overall["per_true_label"].items():
            lines.append(f"| {label} | {e['truths']} | {e['matched']} | "
                         + " | ".join(_cell(e["recall"][n]) for n in CRITERIA) + " |")
    if "tracking" in summary:
        lines += [""] + tracking_lines(summary["tracking"])
    lines += ["", "## Histograms", "", "![centre error](centre_error.png)",
              "![yaw error](yaw_error.png)", "![size error](size_error.png)",
              "![IoU](iou.png)"]
    write_file(path, ("\n".join(lines) + "\n").encode(), "index")


def plot_histograms(errors, folder):
    import matplotlib

    matplotlib.use("Agg")  # Files only: no display needed.
    import matplotlib.pyplot as plt

    def values(key):
        return np.array([e[key] for e in errors], float)

    def figure(panels, name, title):
        fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.4),
                                 squeeze=False)
        for ax, (series, xlabel, lines, bins) in zip(axes[0], panels):
            if not errors:
                ax.text(0.5, 0.5, "no matched pairs", ha="center", va="center",
                        transform=ax.transAxes)
            for data, label in series:
                if len(data):
                    # Outlines when several series share a panel, so that each stays visible.
                    ax.hist(data, bins=bins, label=label, linewidth=1.5,
                            histtype="step" if len(series) > 1 else "bar")
            for x in lines:
                ax.axvline(x, color="k", linestyle="--", linewidth=1)
            ax.set_xlabel(xlabel)
            ax.set_ylabel("matched pairs")
            if len(series) > 1 and errors:
                ax.legend(fontsize=8)
        fig.suptitle(f"{title}, {len(errors)} matched pairs", fontsize=10)
        fig.tight_layout()
        try:
            save_figure(fig, os.path.join(folder, name))
        finally:
            plt.close(fig)

    top = max(1.0, float(values("centre_3d_m").max()) if errors else 1.0)
    figure([([(values("centre_3d_m"), "3-D"), (values("centre_xy_m"), "x-y")],
             "centre error (m)", [CENTRE_TOLERANCE_M], np.linspace(0, top, 41))],
           "centre_error.png", "Centre error")
    figure([([(values("yaw_deg"), "yaw")], "yaw error modulo 180 (degrees)",
             [YAW_TOLERANCE_DEG], np.linspace(0, 90, 46))], "yaw_error.png", "Yaw error")
    size_panels = []
    for key, name in (("length_m", "length"), ("width_m", "width"), ("height_m", "height")):
        data = values(key)
        span = max(0.5, float(np.abs(data).max()) if len(data) else 0.5)
        size_panels.append(([(data, name)], f"{name} error, predicted - true (m)", [0.0],
                            np.linspace(-span, span, 42)))
    figure(size_panels, "size_error.png", "Size errors")
    figure([([(values("bev_iou"), "bird's-eye"), (values("iou_3d"), "3-D")], "IoU",
             [0.5, 0.7], np.linspace(0, 1, 41))], "iou.png", "IoU")


def write_report(folder, summary, errors):
    """summary.json, index.md and the histograms into `folder` (a staging folder)."""
    write_file(os.path.join(folder, "summary.json"),
               json.dumps(summary, indent=1, allow_nan=False).encode(), "summary")
    write_index(os.path.join(folder, "index.md"), summary)
    plot_histograms(errors, folder)


def printed_table(summary):
    overall, frames = summary["overall"], summary["frames"]
    lines = [f"{TOOL}: {frames['truth']} frames ({len(frames['without_predictions'])} without "
             f"predictions, {len(frames['only_predicted_ignored'])} prediction files without "
             f"truth ignored); {overall['truths']} truths ({overall['truths_ignored']} don't "
             f"care), {overall['predictions']} predictions ({overall['predictions_ignored']} "
             f"ignored), {overall['matched']} matched",
             f"  {'criterion':<30} {'TP':>5} {'FP':>5} {'FN':>5} {'prec':>6} {'recall':>6} "
             f"{'F1':>6}  {'class-aware F1':>14}"]
    classless = unclassified(overall)
    for name in CRITERIA:
        s, c = overall["criteria"][name], overall["class_aware"][name]
        class_aware = "-" if classless else _cell(c["f1"])
        lines.append(f"  {CRITERION_TITLES[name]:<30} {s['tp']:>5} {s['fp']:>5} {s['fn']:>5} "
                     f"{_cell(s['precision']):>6} {_cell(s['recall']):>6} {_cell(s['f1']):>6}"
                     f"  {class_aware:>14}")
    if classless:
        lines.append(f"  class-aware: {UNCLASSIFIED_NOTE}")
    e = overall["errors"]
    lines.append(f"  median errors: centre {_cell(e['centre_3d_m']['median'])} m, yaw "
                 f"{_cell(e['yaw_deg']['median'], 2)} deg, length "
                 f"{_cell(e['length_m']['median'])} m, width {_cell(e['width_m']['median'])} m, "
                 f"height {_cell(e['height_m']['median'])} m")
    if "tracking" in summary:
        t = summary["tracking"]
        lines.append(f"  tracking (paper's criterion): MOTA {_cell(t['mota'])}, "
                     f"{t['id_switches']} ID switches "
                     f"({_cell(t['id_switches_per_100_track_frames'], 2)} per 100 track-frames), "
                     f"{t['vehicles_followed']} vehicles followed by {t['tracks_following']} "
                     f"tracks; {t['class_settled_tracks']} tracks settled on their class, in "
                     f"{_cell(t['frames_to_settle']['median'], 1)} frames (median); "
                     f"class-aware F1 per track {_cell(t['class_aware_f1_per_track'])}")
    return "\n".join(lines)


def _positive(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of metres, got {text!r}") from None
    if not value > 0 or not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a positive number of metres, got {text}")
    return value


def _count(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {text}")
    return value


def parser():
    default_map = ", ".join(f"{p} as {'/'.join(t)}" for p, t in DEFAULT_CLASS_MAP.items())
    p = argparse.ArgumentParser(
        prog=TOOL,
        description="Score predicted cuboids against true ones, frame by frame. Both are "
                    "folders of <stamp>.json in the layout of a frames folder's detections_3d/ "
                    "(a frames folder is taken for its detections_3d/). Per frame, predictions "
                    "are matched one-to-one to truths (Hungarian assignment on the x-y centre "
                    "distance, pairs farther than --gate never match); the same pairs are "
                    "scored under the paper's criterion (3-D centre distance < 0.5 m and yaw "
                    "difference modulo 180 degrees < 10 degrees), bird's-eye IoU > 0.5 and > "
                    "0.7, and 3-D IoU > 0.5 and > 0.7, class-agnostic and class-aware. Writes "
                    "R/summary.json (overall and per frame), R/index.md and histograms of "
                    "the centre, yaw, size and IoU errors of matched pairs. Exit status: 0 "
                    "done, 1 failed, 2 bad option or class map, 130/143 interrupted.",
        epilog="Truth frames without a predictions file count as frames with no predictions; "
               "prediction files without truth are ignored. Truths left out by --max-range, "
               "--field-of-view, --min-points or --labels are \"don't care\": not counted as missed, and a "
               "prediction matched to one is not a false positive (nor is an unmatched "
               "prediction beyond --max-range). See docs/cuboids.md.")
    p.add_argument("--truth", required=True, metavar="T",
                   help="true cuboids: a frames folder (its detections_3d/, and pcd/ for "
                        "--min-points) or a folder of <stamp>.json")
    p.add_argument("--predicted", required=True, metavar="D",
                   help="predicted cuboids: a folder of <stamp>.json (or a frames folder)")
    p.add_argument("--out", required=True, metavar="R",
                   help="report folder (created; must not hold results unless --overwrite; a "
                        "folder of other files is never replaced)")
    p.add_argument("--class-map", metavar="FILE.yaml",
                   help="YAML mapping of a predicted label to the true label(s) it counts as "
                        "(e.g. 'Sedan: Car' or 'Sedan: [Car, Vehicle]'); replaces the default "
                        f"({default_map}); every label always counts as itself")
    p.add_argument("--max-range", type=_positive, metavar="M",
                   help="evaluate only truths whose centre is within M metres (x-y) of the "
                        "frame's origin, the sensor (default: no limit)")
    p.add_argument("--field-of-view", type=_positive, metavar="DEG",
                   help="evaluate only truths within DEG degrees either side of straight ahead "
                        "(+x), and ignore unmatched predictions outside them: the camera's view "
                        "of camera-labelled data (KITTI: 40; default: all around)")
    p.add_argument("--min-points", type=_count, metavar="N",
                   help="evaluate only truths with at least N points of the frame's cloud "
                        "inside the box (needs --truth to be a frames folder)")
    p.add_argument("--labels", nargs="+", metavar="LABEL",
                   help="evaluate only truths with these labels (default: every label)")
    p.add_argument("--gate", type=_positive, default=GATE_M, metavar="M",
                   help=f"largest x-y centre distance of a matched pair (default: {GATE_M:g} m)")
    p.add_argument("--tracking", action="store_true",
                   help="the predicted ids are track ids and the true ids vehicles: also score "
                        "the tracks (MOTA, identity switches per 100 track-frames and the "
                        "frames a track needs to settle on its class; docs/tracking.md)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an output folder that holds an earlier report")
    p.add_argument("--quiet", action="store_true", help="no progress and no printed table")
    return p


def main(argv=None):
    args = parser().parse_args(argv)

    def body():
        check_output_apart(args.out, (args.truth, args.predicted), UsageError)
        class_map, source = DEFAULT_CLASS_MAP, "default"
        if args.class_map:
            class_map, source = load_class_map(args.class_map), args.class_map
        settings = Settings(args.truth, args.predicted, class_map,
                            Filters(args.max_range, args.min_points,
                                    tuple(args.labels) if args.labels else None,
                                    args.field_of_view),
                            args.gate, source, args.tracking)
        reporter = None if args.quiet else progress.Reporter(TOOL, unit="frames")
        # Entered first: an output that may not be written is refused before the work.
        with OutputFolder(args.out, TOOL, args.overwrite) as folder:
            summary, errors = evaluate(settings, reporter)
            if reporter:
                reporter.finish()
            table = printed_table(summary)
            write_report(folder.staging, summary, errors)
            folder.commit()
        if not args.quiet:
            skipped = summary["skipped_boxes"]
            if any(sum(reasons.values()) for reasons in skipped.values()):
                sides = [f"{sum(skipped[side].values())} {name}" + (
                    " (" + ", ".join(f"{count} {why}" for why, count in
                                     sorted(skipped[side].items())) + ")"
                    if skipped[side] else "") for side, name in (("truth", "true"),
                                                                 ("predicted", "predicted"))]
                print(f"{TOOL}: boxes skipped as invalid: {', '.join(sides)}")
            print(table)
            print(f"{TOOL}: {os.path.join(args.out, 'index.md')}")
        return 0

    return run_main(TOOL, body, (CuboidError, DetectionsError, CloudError, OutputError, OSError))
