"""Predicted cuboids against true ones, frame by frame: one-to-one matching (a Hungarian
assignment on the x-y centre distance, gated), the errors of each pair and the precision,
recall and F1 under each criterion. The detections are read by frames_folder; evaluate_cuboids
(cuboids.py) writes the report. (Over 400 lines: the matching, the filters and the tally share
their types.)"""
import collections
import dataclasses
import math
import os

import numpy as np
import yaml

from ..frames_folder import (CLOUDS_FOLDER, DETECTIONS_FOLDER, detections_folder, frame_files,
                             load_detections)
from ..geometry import bev_iou, count_points_inside, iou_3d, yaw_difference_deg
from ..labels import UNKNOWN
from ..output import absolute
from ..pcd import read_pcd

TOOL = "evaluate_cuboids"
GATE_M = 2.0
CENTRE_TOLERANCE_M = 0.5  # the paper's SSE < 0.25 m^2 on x, y, z
YAW_TOLERANCE_DEG = 10.0
# Predicted label -> true labels it also counts as (every label counts as itself).
DEFAULT_CLASS_MAP = {"Sedan": ("Car",), "SUV": ("Car",), "Hatchback": ("Car",),
                     "Jeep": ("Car",)}

CRITERIA = {
    "paper": f"3-D centre distance < {CENTRE_TOLERANCE_M} m and yaw difference modulo 180 "
             f"degrees < {YAW_TOLERANCE_DEG:g} degrees",
    "bev_iou_0.5": "bird's-eye IoU > 0.5",
    "bev_iou_0.7": "bird's-eye IoU > 0.7",
    "iou_3d_0.5": "3-D IoU > 0.5",
    "iou_3d_0.7": "3-D IoU > 0.7",
}
CRITERION_TITLES = {"paper": "centre < 0.5 m, yaw < 10 deg", "bev_iou_0.5": "BEV IoU > 0.5",
                    "bev_iou_0.7": "BEV IoU > 0.7", "iou_3d_0.5": "3-D IoU > 0.5",
                    "iou_3d_0.7": "3-D IoU > 0.7"}


class CuboidError(ValueError):
    """Input that cannot be evaluated; the message names the file or folder. Exit 1."""


class UsageError(CuboidError):
    """A bad option or class map. Exit 2."""
    status = 2


# ---------------------------------------------------------------------------- input

def load_class_map(path):
    """{predicted label: (true labels,)} from a YAML mapping of a label to a label or a list."""
    try:
        with open(path, encoding="utf-8") as stream:
            values = yaml.safe_load(stream)
    except OSError as error:
        raise UsageError(f"{path}: cannot read the class map: {error.strerror}") from error
    except UnicodeDecodeError as error:
        raise UsageError(f"{path}: the class map is not UTF-8 text (byte {error.start})") \
            from error
    except (yaml.YAMLError, RecursionError) as error:
        raise UsageError(f"{path}: class map is not valid YAML: "
                         f"{' '.join(str(error).split())}") from error
    if values is None:
        return {}
    if not isinstance(values, dict):
        raise UsageError(f"{path}: the class map must be a mapping of predicted label to true "
                         "label(s), e.g. 'Sedan: Car'")
    class_map = {}
    for predicted, true in values.items():
        true = [true] if isinstance(true, str) else true
        if not isinstance(predicted, str) or not isinstance(true, list) or \
                not all(isinstance(t, str) for t in true):
            raise UsageError(f"{path}: {predicted!r}: expected a predicted label mapped to a "
                             f"true label or a list of true labels, got {true!r}")
        class_map[predicted] = tuple(true)
    return class_map


def counts_as(predicted, true, class_map):
    return predicted == true or true in class_map.get(predicted, ())


def load_cloud(path):
    """x, y, z (N x 3, float64, finite rows) of a PCD."""
    try:
        _, points, _, _ = read_pcd(path)
    except OSError as error:
        raise CuboidError(f"{path}: cannot read the cloud: {error.strerror}") from error
    names = points.dtype.names or ()
    missing = [a for a in "xyz" if a not in names]
    if missing:
        raise CuboidError(f"{path}: PCD has no {'/'.join(missing)} field")
    xyz = np.stack([points[a] for a in "xyz"], axis=1).astype(float)
    return xyz[np.all(np.isfinite(xyz), axis=1)]


# ---------------------------------------------------------------------------- matching

def match(truths, predictions, gate):
    """One-to-one pairs (truth index, prediction index) minimising the total x-y centre
    distance among the assignments with the most pairs within `gate` metres; pairs farther
    than the gate never match."""
    if not truths or not predictions:
        return []
    from scipy.optimize import linear_sum_assignment

    t = np.array([d.box.centre[:2] for d in truths])
    p = np.array([d.box.centre[:2] for d in predictions])
    distance = np.linalg.norm(t[:, None, :] - p[None, :, :], axis=2)
    admissible = distance <= gate
    # A pair beyond the gate costs more than any set of admissible pairs, so the assignment
    # first has the most admissible pairs, then the smallest total distance.
    forbidden = (min(len(t), len(p)) + 1) * gate + 1.0
    rows, columns = linear_sum_assignment(np.where(admissible, distance, forbidden))
    return [(int(i), int(j)) for i, j in zip(rows, columns) if admissible[i, j]]


def pair_errors(truth, prediction):
    """Geometric errors of a matched pair (prediction minus truth for sizes)."""
    a, b = truth.box, prediction.box
    offset = np.subtract(b.centre, a.centre)
    return {
        "centre_3d_m": float(np.linalg.norm(offset)),
        "centre_xy_m": float(np.linalg.norm(offset[:2])),
        "yaw_deg": yaw_difference_deg(b.yaw, a.yaw),
        "length_m": b.size[0] - a.size[0],
        "width_m": b.size[1] - a.size[1],
        "height_m": b.size[2] - a.size[2],
        "bev_iou": bev_iou(a, b),
        "iou_3d": iou_3d(a, b),
    }


def passes(errors):
    """{criterion: bool} of a matched pair."""
    return {
        "paper": errors["centre_3d_m"] < CENTRE_TOLERANCE_M and
        errors["yaw_deg"] < YAW_TOLERANCE_DEG,
        "bev_iou_0.5": errors["bev_iou"] > 0.5, "bev_iou_0.7": errors["bev_iou"] > 0.7,
        "iou_3d_0.5": errors["iou_3d"] > 0.5, "iou_3d_0.7": errors["iou_3d"] > 0.7,
    }


@dataclasses.dataclass
class Filters:
    max_range: float = None  # metres, x-y distance of the true centre from the frame's origin
    min_points: int = None  # points of the frame's cloud inside the true box
    labels: tuple = None  # true labels evaluated
    # degrees either side of straight ahead (+x): the camera's view of camera-labelled data
    field_of_view: float = None

    def active(self):
        return (self.max_range is not None or self.min_points is not None or bool(self.labels)
                or self.field_of_view is not None)

    def outside(self, centre):
        """Whether a centre lies beyond the range or outside the field of view."""
        if self.max_range is not None and math.hypot(*centre[:2]) > self.max_range:
            return True
        return (self.field_of_view is not None and
                abs(math.degrees(math.atan2(centre[1], centre[0]))) > self.field_of_view)

    def why_ignored(self, truth, points=None):
        """None when the truth is evaluated, else the reason it is "don't care"."""
        if self.labels and truth.label not in self.labels:
            return "label"
        if self.outside(truth.box.centre):
            return "range"
        if self.min_points is not None and points < self.min_points:
            return "points"
        return None


@dataclasses.dataclass
class FrameResult:
    truths: list
    predictions: list
    ignored_truths: dict  # truth index -> reason
    pairs: list  # (truth index, prediction index, errors, passes, same class)
    ignored_predictions: dict  # prediction index -> reason
    points: list = None  # points inside each true box, with --min-points


def evaluate_frame(truths, predictions, filters, class_map, gate, xyz=None):
    """Match and score one frame. KITTI's order: predictions are matched to the evaluated
    truths first; those left over are matched to the "don't care" truths and then ignored,
    as are unmatched predictions beyond the range filter."""
    points = [count_points_inside(xyz, t.box) for t in truths] if xyz is not None else None
    ignored = {}
    for i, truth in enumerate(truths):
        why = filters.why_ignored(truth, points[i] if points is not None else None)
        if why:
            ignored[i] = why
    counted = [i for i in range(len(truths)) if i not in ignored]
    pairs = []
    for ti, pi in match([truths[i] for i in counted], predictions, gate):
        truth, prediction = truths[counted[ti]], predictions[pi]
        errors = pair_errors(truth, prediction)
        pairs.append((counted[ti], pi, errors, passes(errors),
                      counts_as(prediction.label, truth.label, class_map)))
    left = [j for j in range(len(predictions)) if j not in {p[1] for p in pairs}]
    dont_care = sorted(ignored)
    ignored_predictions = {}
    for ti, pi in match([truths[i] for i in dont_care], [predictions[j] for j in left], gate):
        ignored_predictions[left[pi]] = f"matched a truth ignored for its {ignored[dont_care[ti]]}"
    for j in left:
        if j not in ignored_predictions and filters.outside(predictions[j].box.centre):
            ignored_predictions[j] = "beyond the range or outside the field of view"
    return FrameResult(truths, predictions, ignored, pairs, ignored_predictions, points)


# ---------------------------------------------------------------------------- scores

def scores(tp, truths, predictions):
    """TP, FP, FN, precision (None without predictions), recall (None without truths) and
    F1 = 2 TP / (2 TP + FP + FN) (None when both are empty)."""
    fp, fn = predictions - tp, truths - tp
    return {"tp": tp, "fp": fp, "fn": fn,
            "precision": tp / predictions if predictions else None,
            "recall": tp / truths if truths else None,
            "f1": 2 * tp / (2 * tp + fp + fn) if truths + predictions else None}


class Tally:
    """Counts over one frame or many."""

    def __init__(self):
        self.truths = self.predictions = self.matched = 0
        self.truths_ignored = self.predictions_ignored = 0
        self.unclassified = 0  # counted predictions labelled unknown
        self.tp = collections.Counter()
        self.tp_class = collections.Counter()

    def add(self, result):
        self.truths += len(result.truths) - len(result.ignored_truths)
        self.truths_ignored += len(result.ignored_truths)
        self.predictions += len(result.predictions) - len(result.ignored_predictions)
        self.predictions_ignored += len(result.ignored_predictions)
        self.unclassified += sum(prediction.label == UNKNOWN
                                 for j, prediction in enumerate(result.predictions)
                                 if j not in result.ignored_predictions)
        self.matched += len(result.pairs)
        for _, _, _, passed, same_class in result.pairs:
            for name, ok in passed.items():
                self.tp[name] += ok
                self.tp_class[name] += ok and same_class

    def summary(self):
        return {
            "truths": self.truths, "truths_ignored": self.truths_ignored,
            "predictions": self.predictions, "predictions_ignored": self.predictions_ignored,
            "unclassified_predictions": self.unclassified, "matched": self.matched,
            "criteria": {n: scores(self.tp[n], self.truths, self.predictions) for n in CRITERIA},
            "class_aware": {n: scores(self.tp_class[n], self.truths, self.predictions)
                            for n in CRITERIA},
        }


def distribution(values):
    """count, median, mean and 90th percentile (None when empty)."""
    if not values:
        return {"count": 0, "median": None, "mean": None, "p90": None}
    array = np.asarray(values, float)
    return {"count": len(array), "median": float(np.median(array)), "mean": float(array.mean()),
            "p90": float(np.percentile(array, 90))}


ERROR_KEYS = ("centre_3d_m", "centre_xy_m", "yaw_deg", "length_m", "width_m", "height_m",
              "bev_iou", "iou_3d")
SIGNED_KEYS = ("length_m", "width_m", "height_m")


def error_summary(errors):
    """Distributions of the matched pairs' errors: sizes as absolute errors, with the mean
    signed error (prediction minus truth) beside."""
    out = {}
    for key in ERROR_KEYS:
        values = [e[key] for e in errors]
        if key in SIGNED_KEYS:
            out[key] = {**distribution([abs(v) for v in values]),
                        "mean_signed": float(np.mean(values)) if values else None}
        else:
            out[key] = distribution(values)
    return out


def _rounded(errors):
    return {k: round(v, 6) for k, v in errors.items()}


def frame_record(result, tally):
    pairs = [{"truth_id": result.truths[ti].id, "predicted_id": result.predictions[pi].id,
              "truth_label": result.truths[ti].label,
              "predicted_label": result.predictions[pi].label, "same_class": same_class,
              **_rounded(errors), "passes": [n for n, ok in passed.items() if ok]}
             for ti, pi, errors, passed, same_class in result.pairs]
    matched_truths = {p[0] for p in result.pairs}
    matched_predictions = {p[1] for p in result.pairs}
    record = tally.summary()
    record.update({
        "pairs": pairs,
        "missed_truth_ids": [t.id for i, t in enumerate(result.truths)
                             if i not in matched_truths and i not in result.ignored_truths],
        "unmatched_predicted_ids": [p.id for j, p in enumerate(result.predictions)
                                    if j not in matched_predictions and
                                    j not in result.ignored_predictions],
        "ignored_truths": {str(result.truths[i].id): why
                           for i, why in sorted(result.ignored_truths.items())},
        "ignored_predictions": {str(result.predictions[j].id): why
                                for j, why in sorted(result.ignored_predictions.items())},
    })
    if result.points is not None:
        record["points_in_truths"] = {str(t.id): n for t, n in zip(result.truths, result.points)}
    return record


# ---------------------------------------------------------------------------- run

@dataclasses.dataclass
class Settings:
    truth: str
    predicted: str
    class_map: dict
    filters: Filters
    gate: float = GATE_M
    class_map_source: str = "default"
    tracking: bool = False  # the predicted ids are track ids: score them as tracks (tracks.py)


def evaluate(settings, reporter=None):
    """The whole evaluation, no files written: (summary dictionary, errors of every counted
    matched pair)."""
    truth_folder, clouds = detections_folder(settings.truth, "truth")
    predicted_folder, _ = detections_folder(settings.predicted, "predictions")
    if settings.filters.min_points is not None and clouds is None:
        raise UsageError(f"{settings.truth}: --min-points needs the clouds: give --truth a "
                         f"frames folder (with {DETECTIONS_FOLDER}/ and {CLOUDS_FOLDER}/)")
    truth_files, predicted_files = frame_files(truth_folder), frame_files(predicted_folder)
    if not truth_files:
        raise CuboidError(f"{truth_folder}: no <stamp>.json detection files")
    without_predictions = [s for s in truth_files if s not in predicted_files]
    only_predicted = [s for s in predicted_files if s not in truth_files]

    overall, per_frame, all_errors = Tally(), {}, []
    skipped = {"truth": collections.Counter(), "predicted": collections.Counter()}
    labels = collections.defaultdict(lambda: {"truths": 0, "matched": 0,
                                              "tp": collections.Counter(),
                                              "tp_class": collections.Counter()})
    labels_seen = set()
    tracks = None
    if settings.tracking:
        from .tracks import TrackTally  # here: tracks.py builds on this module
        tracks = TrackTally(settings.class_map)
    for k, (stamp, truth_path) in enumerate(truth_files.items()):
        truths, dropped = load_detections(truth_path)
        skipped["truth"].update(dropped)
        labels_seen.update(truth.label for truth in truths)
        predictions = []
        if stamp in predicted_files:
            predictions, dropped = load_detections(predicted_files[stamp])
            skipped["predicted"].update(dropped)
        xyz = None
        if settings.filters.min_points is not None:
            xyz = load_cloud(os.path.join(clouds, stamp + ".pcd"))
        result = evaluate_frame(truths, predictions, settings.filters, settings.class_map,
                                settings.gate, xyz)
        frame = Tally()
        frame.add(result)
        overall.add(result)
        if tracks:
            tracks.add(result)
        per_frame[stamp] = frame_record(result, frame)
        all_errors += [p[2] for p in result.pairs]
        for i, truth in enumerate(truths):
            if i not in result.ignored_truths:
                labels[truth.label]["truths"] += 1
        for ti, _, _, passed, same_class in result.pairs:
            entry = labels[truths[ti].label]
            entry["matched"] += 1
            for name, ok in passed.items():
                entry["tp"][name] += ok
                entry["tp_class"][name] += ok and same_class
        if reporter:
            reporter(k + 1, len(truth_files))
    # A label asked for that no true box carries is a typo more often than not; none matched
    # would look like an evaluation of nothing.
    if settings.filters.labels and not labels_seen & set(settings.filters.labels):
        raise CuboidError(f"{truth_folder}: no true box carries any of the labels asked for "
                          f"({', '.join(settings.filters.labels)}); labels seen: "
                          f"{', '.join(sorted(labels_seen)) or 'none'}")

    per_label = {label: {"truths": e["truths"], "matched": e["matched"],
                         "recall": {n: e["tp"][n] / e["truths"] for n in CRITERIA},
                         "recall_class_aware": {n: e["tp_class"][n] / e["truths"]
                                                for n in CRITERIA}}
                 for label, e in sorted(labels.items()) if e["truths"]}
    filters = settings.filters
    tracking = {"tracking": tracks.summary()} if tracks else {}
    return {
        "tool": TOOL,
        "truth": absolute(truth_folder), "predicted": absolute(predicted_folder),
        "settings": {
            "gate_m": settings.gate,
            "matching": "Hungarian assignment on the x-y centre distance, pairs farther than "
                        "the gate never match; the same pairs for every criterion",
            "max_range_m": filters.max_range, "field_of_view_deg": filters.field_of_view,
            "min_points": filters.min_points,
            "labels": list(filters.labels) if filters.labels else None,
            "class_map": {k: list(v) for k, v in sorted(settings.class_map.items())},
            "class_map_source": settings.class_map_source,
            "criteria": CRITERIA,
        },
        "frames": {"truth": len(truth_files), "predicted": len(predicted_files),
                   "without_predictions": without_predictions,
                   "only_predicted_ignored": only_predicted},
        "skipped_boxes": {side: dict(sorted(c.items())) for side, c in skipped.items()},
        "overall": {**overall.summary(), "errors": error_summary(all_errors),
                    "per_true_label": per_label},
        **tracking,
        "per_frame": per_frame,
    }, all_errors


# ---------------------------------------------------------------------------- report
