"""evaluate_cuboids: overlaps against hand-computed values, matching, criteria, class map,
filters, the report, and bad input."""
import json
import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from granular_tools import geometry
from granular_tools.evaluation import cuboid_matching, cuboids
from granular_tools.frames_folder import Detection
from granular_tools.geometry import from_yaw

SCRIPT = pathlib.Path(__file__).resolve().parents[1] / "scripts" / "evaluate_cuboids"
STAMP, OTHER_STAMP = "1586102742099223854", "1586102742299319911"


def square(x=0.0, y=0.0, yaw_deg=0.0, z=0.0, side=1.0, height=1.0):
    return from_yaw(x, y, z, side, side, height, math.radians(yaw_deg))


# ---------------------------------------------------------------------------- overlaps

def test_unit_squares_turned_45_degrees_overlap_in_a_regular_octagon():
    a, b = square(), square(yaw_deg=45)
    assert geometry.bev_intersection(a, b) == pytest.approx(2 * (math.sqrt(2) - 1), abs=1e-12)
    assert geometry.bev_iou(a, b) == pytest.approx(math.sqrt(2) / 2, abs=1e-12)  # 0.7071...
    assert geometry.iou_3d(a, b) == pytest.approx(math.sqrt(2) / 2, abs=1e-12)


def test_identical_disjoint_and_half_shifted_boxes():
    box = from_yaw(3.0, -2.0, 0.5, 4.5, 1.8, 1.5, math.radians(30))
    assert geometry.bev_iou(box, box) == pytest.approx(1.0, abs=1e-12)
    assert geometry.iou_3d(box, box) == pytest.approx(1.0, abs=1e-12)
    assert geometry.bev_iou(square(), square(x=1.01)) == 0.0
    assert geometry.iou_3d(square(), square(z=1.01)) == 0.0  # same footprint, no z overlap
    # Half a side along x: 0.5 in common over 1.5 covered.
    assert geometry.bev_iou(square(), square(x=0.5)) == pytest.approx(1 / 3, abs=1e-12)
    # The same turned 90 degrees: a square's footprint does not change.
    assert geometry.bev_iou(square(), square(y=0.5, yaw_deg=90)) == pytest.approx(1 / 3)


def test_3d_iou_multiplies_the_footprint_overlap_by_the_z_overlap():
    a = from_yaw(0.0, 0.0, 0.0, 2.0, 2.0, 2.0, 0.0)
    b = from_yaw(1.0, 0.0, 1.0, 2.0, 2.0, 2.0, 0.0)
    # Footprints share 2 m^2 of 4 each; z ranges [-1, 1] and [0, 2] share 1 m: 2 m^3 of 8 each.
    assert geometry.bev_iou(a, b) == pytest.approx(2 / 6)
    assert geometry.iou_3d(a, b) == pytest.approx(2 / 14)
    # A taller box over the same footprint: 8 m^3 common, 8 + 16 - 8 covered.
    tall = from_yaw(0.0, 0.0, 1.0, 2.0, 2.0, 4.0, 0.0)
    assert geometry.iou_3d(a, tall) == pytest.approx(8 / 16)


def test_yaw_is_the_heading_of_the_box_x_axis_whatever_the_roll():
    yaw, roll = math.radians(40), math.radians(4)
    # q = q_z(yaw) * q_x(roll)
    cz, sz, cx, sx = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(roll / 2), math.sin(roll / 2)
    q = (cz * sx, sz * sx, sz * cx, cz * cx)
    assert geometry.yaw_of_quaternion(q) == pytest.approx(yaw)


def test_yaw_difference_is_taken_modulo_180_degrees():
    deg = math.radians
    assert geometry.yaw_difference_deg(deg(185), deg(0)) == pytest.approx(5)
    assert geometry.yaw_difference_deg(deg(-175), deg(10)) == pytest.approx(5)
    assert geometry.yaw_difference_deg(deg(350), deg(10)) == pytest.approx(20)
    assert geometry.yaw_difference_deg(deg(90), deg(0)) == pytest.approx(90)


def test_points_inside_a_turned_box():
    box = from_yaw(10.0, 0.0, 0.0, 4.0, 2.0, 2.0, math.radians(90))  # long along y
    xyz = np.array([[10.0, 1.9, 0.0], [11.5, 0.0, 0.0], [10.0, 0.0, 1.2], [10.9, -1.9, 0.9]])
    assert geometry.count_points_inside(xyz, box) == 2


# ---------------------------------------------------------------------------- files

def box_json(id_, label, x, y, z=0.0, yaw_deg=0.0, size=(4.5, 1.8, 1.5), score=1.0):
    half = math.radians(yaw_deg) / 2
    header = {"stamp": {"secs": 1, "nsecs": 0}, "frame_id": "velodyne", "seq": 0}
    return {"header": header, "id": id_, "label": label, "score": score,
            "bbox": {"position": {"position": {"x": x, "y": y, "z": z},
                                  "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(half),
                                                  "w": math.cos(half)}},
                     "size": dict(zip("xyz", size))},
            "velocity": {"linear": {"x": 0.0, "y": 0.0, "z": 0.0},
                         "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}}


def write_frames(folder, frames):
    """frames: {stamp: [box_json, ...]} as <stamp>.json in `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    for stamp, boxes in frames.items():
        document = {"header": {"stamp": {"secs": 1, "nsecs": 0}, "frame_id": "velodyne",
                               "seq": 0}, "detections": boxes}
        (folder / f"{stamp}.json").write_text(json.dumps(document))
    return folder


def write_pcd(path, xyz):
    path.parent.mkdir(parents=True, exist_ok=True)
    points = np.asarray(xyz, "<f4")
    header = (f"# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
              f"WIDTH {len(points)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(points)}\n"
              "DATA binary\n")
    path.write_bytes(header.encode() + points.tobytes())


def evaluate(tmp_path, truth, predicted, *extra):
    """Run the tool on {stamp: boxes} dictionaries; return (exit status, summary or None)."""
    truth_folder = truth if isinstance(truth, pathlib.Path) else \
        write_frames(tmp_path / "truth", truth)
    predicted_folder = predicted if isinstance(predicted, pathlib.Path) else \
        write_frames(tmp_path / "predicted", predicted)
    out = tmp_path / "report"
    status = cuboids.main(["--truth", str(truth_folder), "--predicted", str(predicted_folder),
                           "--out", str(out), "--overwrite", "--quiet", *extra])
    summary = json.loads((out / "summary.json").read_text()) if status == 0 else None
    return status, summary


def counts(summary, criterion="paper", kind="criteria"):
    s = summary["overall"][kind][criterion]
    return s["tp"], s["fp"], s["fn"]


# ---------------------------------------------------------------------------- matching

def test_a_prediction_nearest_to_two_truths_goes_to_one_only(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0), box_json(2, "Car", 0.0, 0.8)]}
    predicted = {STAMP: [box_json(7, "Car", 0.0, 0.3)]}
    status, summary = evaluate(tmp_path, truth, predicted)
    assert status == 0
    assert summary["overall"]["matched"] == 1
    assert counts(summary) == (1, 0, 1)
    assert summary["per_frame"][STAMP]["pairs"][0]["truth_id"] == 1
    assert summary["per_frame"][STAMP]["missed_truth_ids"] == [2]


def test_the_assignment_minimises_the_total_distance_not_each_greedily():
    truths = [Detection(i, "Car", 1.0, square(x=x)) for i, x in ((1, 0.0), (2, 1.2))]
    # Prediction 0 is nearest to both truths; greedy would give it truth 2 (0.5 m) and leave
    # prediction 1 at 1.9 m from truth 1. Hungarian: 0.7 + 0.7.
    predictions = [Detection(i, "Car", 1.0, square(x=x)) for i, x in ((7, 0.7),
                                                                                (8, 1.9))]
    assert sorted(cuboid_matching.match(truths, predictions, gate=2.0)) == [(0, 0), (1, 1)]
    # Beyond the gate, never.
    assert cuboid_matching.match(truths[:1], predictions[1:], gate=1.5) == []


def test_the_gate_keeps_far_pairs_apart(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0)]}
    predicted = {STAMP: [box_json(7, "Car", 2.5, 0.0)]}
    _, summary = evaluate(tmp_path, truth, predicted)
    assert summary["overall"]["matched"] == 0 and counts(summary, "bev_iou_0.5") == (0, 1, 1)
    _, summary = evaluate(tmp_path, truth, predicted, "--gate", "3")
    assert summary["overall"]["matched"] == 1
    # 2 m of 4.5 m overlap: IoU 2 / 7 fails 0.5 however it is matched.
    assert counts(summary, "bev_iou_0.5") == (0, 1, 1)
    assert summary["per_frame"][STAMP]["pairs"][0]["bev_iou"] == pytest.approx(2 / 7, abs=1e-6)


def test_papers_criterion_takes_yaw_modulo_180_and_the_3d_centre(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0), box_json(2, "Car", 20.0, 0.0),
                     box_json(3, "Car", 40.0, 0.0), box_json(4, "Car", 60.0, 0.0),
                     box_json(5, "Car", 80.0, 0.0)]}
    predicted = {STAMP: [
        box_json(11, "Car", 0.4, 0.0, yaw_deg=180),  # flipped: the same cuboid, passes
        box_json(12, "Car", 20.0, 0.0, yaw_deg=11),  # 11 degrees off: fails
        box_json(13, "Car", 40.0, 0.0, yaw_deg=-9),  # 9 degrees off: passes
        box_json(14, "Car", 60.35, 0.0, z=0.4),  # 0.35 m in x-y, 0.53 m in 3-D: fails
        box_json(15, "Car", 80.0, 0.0, yaw_deg=189),  # flipped and 9 degrees off: passes
    ]}
    _, summary = evaluate(tmp_path, truth, predicted)
    pairs = {p["truth_id"]: p for p in summary["per_frame"][STAMP]["pairs"]}
    assert {i: "paper" in p["passes"] for i, p in pairs.items()} == \
        {1: True, 2: False, 3: True, 4: False, 5: True}
    assert pairs[1]["yaw_deg"] == pytest.approx(0.0, abs=1e-9)
    assert pairs[2]["yaw_deg"] == pytest.approx(11.0)
    assert pairs[4]["centre_xy_m"] == pytest.approx(0.35)
    assert pairs[4]["centre_3d_m"] == pytest.approx(math.hypot(0.35, 0.4))
    assert counts(summary) == (3, 2, 2)
    paper = summary["overall"]["criteria"]["paper"]
    assert paper["precision"] == pytest.approx(3 / 5) and paper["recall"] == pytest.approx(3 / 5)
    assert paper["f1"] == pytest.approx(3 / 5)


def test_iou_criteria_are_strict_and_errors_are_summarised(tmp_path):
    # Unit-square footprints turned 45 degrees: BEV IoU 0.7071 passes 0.7; the same with half
    # the height in common (z 0.5 up): 3-D IoU = 0.4142 / (2 - 0.4142) = 0.2612 fails both.
    size = (1.0, 1.0, 1.0)
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0, size=size),
                     box_json(2, "Car", 10.0, 0.0, size=size)]}
    predicted = {STAMP: [box_json(11, "Car", 0.0, 0.0, yaw_deg=45, size=size),
                         box_json(12, "Car", 10.0, 0.0, z=0.5, yaw_deg=45, size=size)]}
    _, summary = evaluate(tmp_path, truth, predicted)
    criteria = summary["overall"]["criteria"]
    assert criteria["bev_iou_0.7"]["tp"] == 2
    assert criteria["iou_3d_0.5"]["tp"] == 1 and criteria["iou_3d_0.7"]["tp"] == 1
    pairs = {p["truth_id"]: p for p in summary["per_frame"][STAMP]["pairs"]}
    half = 2 * (math.sqrt(2) - 1) / 2
    assert pairs[2]["iou_3d"] == pytest.approx(half / (2 - half), abs=1e-6)
    errors = summary["overall"]["errors"]
    assert errors["yaw_deg"]["median"] == pytest.approx(45.0)
    assert errors["centre_3d_m"] == pytest.approx(
        {"count": 2, "median": 0.25, "mean": 0.25, "p90": 0.45})
    # IoU exactly at a threshold does not pass it (KITTI's >): 3 x 3 squares 1 m apart share
    # 6 m^2 of 12 (every number exact in binary floating point).
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0, size=(3.0, 3.0, 1.0))]}
    predicted = {STAMP: [box_json(11, "Car", 1.0, 0.0, size=(3.0, 3.0, 1.0))]}
    _, summary = evaluate(tmp_path, truth, predicted)
    assert summary["per_frame"][STAMP]["pairs"][0]["bev_iou"] == 0.5
    assert summary["overall"]["criteria"]["bev_iou_0.5"]["tp"] == 0


# ---------------------------------------------------------------------------- class map

def test_default_class_map_counts_fine_classes_as_car(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0), box_json(2, "Car", 10.0, 0.0),
                     box_json(3, "Sedan", 20.0, 0.0), box_json(4, "Pedestrian", 30.0, 0.0)]}
    predicted = {STAMP: [box_json(11, "Sedan", 0.0, 0.0), box_json(12, "SchoolBus", 10.0, 0.0),
                         box_json(13, "Hatchback", 20.0, 0.0),
                         box_json(14, "Pedestrian", 30.0, 0.0)]}
    _, summary = evaluate(tmp_path, truth, predicted)
    assert counts(summary) == (4, 0, 0)  # geometry matches whatever the class
    assert counts(summary, kind="class_aware") == (2, 2, 2)  # Sedan->Car, Pedestrian
    same = {p["truth_id"]: p["same_class"] for p in summary["per_frame"][STAMP]["pairs"]}
    assert same == {1: True, 2: False, 3: False, 4: True}
    assert summary["settings"]["class_map"]["Jeep"] == ["Car"]


def test_a_class_map_file_replaces_the_default(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0), box_json(2, "Vehicle", 10.0, 0.0),
                     box_json(3, "Car", 20.0, 0.0)]}
    predicted = {STAMP: [box_json(11, "Sedan", 0.0, 0.0), box_json(12, "Sedan", 10.0, 0.0),
                         box_json(13, "Jeep", 20.0, 0.0)]}
    class_map = tmp_path / "map.yaml"
    class_map.write_text("# predicted: true\nSedan: [Car, Vehicle]\n")
    _, summary = evaluate(tmp_path, truth, predicted, "--class-map", str(class_map))
    same = {p["truth_id"]: p["same_class"] for p in summary["per_frame"][STAMP]["pairs"]}
    assert same == {1: True, 2: True, 3: False}  # Jeep is no longer Car
    class_map.write_text("")  # empty: every label counts only as itself
    _, summary = evaluate(tmp_path, truth, predicted, "--class-map", str(class_map))
    assert counts(summary, kind="class_aware") == (0, 3, 3)


@pytest.mark.parametrize("text, message", [
    ("Sedan: [Car, 3]\n", "'Sedan': expected a predicted label mapped to a true label"),
    ("- Sedan\n- Car\n", "the class map must be a mapping"),
    ("Sedan: [Car\n", "class map is not valid YAML"),
    (b"\xff\xfe Sedan: Car\n", "not UTF-8 text"),
])
def test_a_bad_class_map_is_a_usage_error_naming_the_file(tmp_path, capsys, text, message):
    class_map = tmp_path / "map.yaml"
    if isinstance(text, bytes):
        class_map.write_bytes(text)
    else:
        class_map.write_text(text)
    status, _ = evaluate(tmp_path, {STAMP: []}, {STAMP: []}, "--class-map", str(class_map))
    assert status == 2
    err = capsys.readouterr().err
    assert err.startswith(f"evaluate_cuboids: error: {class_map}: ") and message in err
    assert not (tmp_path / "report").exists()


# ---------------------------------------------------------------------------- frames, filters

def test_missing_prediction_frames_count_as_empty_and_extra_ones_are_ignored(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0)],
             OTHER_STAMP: [box_json(2, "Car", 0.0, 0.0), box_json(3, "Car", 9.0, 0.0)]}
    predicted = write_frames(tmp_path / "predicted", {
        STAMP: [box_json(11, "Car", 0.1, 0.0)], "1586102742400000000": [box_json(12, "Car", 0, 0)]})
    (predicted / ".granular.json").write_text('{"tool": "fit_cuboids"}')  # not a frame
    _, summary = evaluate(tmp_path, truth, predicted)
    assert summary["frames"] == {"truth": 2, "predicted": 2, "without_predictions": [OTHER_STAMP],
                                 "only_predicted_ignored": ["1586102742400000000"]}
    assert counts(summary) == (1, 0, 2)
    assert summary["per_frame"][OTHER_STAMP]["criteria"]["paper"] == {
        "tp": 0, "fp": 0, "fn": 2, "precision": None, "recall": 0.0, "f1": 0.0}
    assert summary["overall"]["criteria"]["paper"]["recall"] == pytest.approx(1 / 3)


def test_truths_outside_the_range_are_dont_care(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 10.0, 0.0), box_json(2, "Car", 0.0, 40.0),
                     box_json(3, "Car", 0.0, -45.0)]}
    predicted = {STAMP: [box_json(11, "Car", 10.0, 0.0),
                         box_json(12, "Car", 0.0, 40.2),  # on a far truth: ignored, not FP
                         box_json(13, "Car", 50.0, 0.0),  # nothing there, far: ignored
                         box_json(14, "Car", 0.0, 20.0)]}  # nothing there, near: FP
    _, summary = evaluate(tmp_path, truth, predicted, "--max-range", "30")
    overall = summary["overall"]
    assert (overall["truths"], overall["truths_ignored"]) == (1, 2)
    assert (overall["predictions"], overall["predictions_ignored"]) == (2, 2)
    assert counts(summary) == (1, 1, 0)
    frame = summary["per_frame"][STAMP]
    assert frame["ignored_truths"] == {"2": "range", "3": "range"}
    assert frame["unmatched_predicted_ids"] == [14]


def test_predictions_go_to_evaluated_truths_before_dont_care_ones(tmp_path):
    # One prediction between a near truth and a Pedestrian left out by --labels: it is the
    # near truth's (KITTI's order), not lost to the don't-care one.
    truth = {STAMP: [box_json(1, "Car", 10.0, 0.0), box_json(2, "Pedestrian", 10.5, 0.0)]}
    predicted = {STAMP: [box_json(11, "Car", 10.4, 0.0)]}
    _, summary = evaluate(tmp_path, truth, predicted, "--labels", "Car", "Sedan")
    assert counts(summary) == (1, 0, 0)
    assert summary["per_frame"][STAMP]["ignored_truths"] == {"2": "label"}


def test_labels_no_true_box_carries_are_an_error_naming_those_seen(tmp_path, capsys):
    # Before: 0 truths evaluated, exit 0, as if the cuboids had been scored.
    truth = {STAMP: [box_json(1, "Car", 10.0, 0.0)]}
    status, _ = evaluate(tmp_path, truth, truth, "--labels", "Zeppelin")
    assert status == 1
    assert "no true box carries any of the labels asked for (Zeppelin); labels seen: Car" in \
        capsys.readouterr().err
    assert not (tmp_path / "report").exists()


def test_min_points_counts_the_clouds_points_in_each_true_box(tmp_path):
    frames = tmp_path / "frames"
    write_frames(frames / "detections_3d", {STAMP: [box_json(1, "Car", 10.0, 0.0),
                                                    box_json(2, "Car", 20.0, 0.0)]})
    rng = np.random.default_rng(5)
    near = rng.uniform([-2, -0.8, -0.7], [2, 0.8, 0.7], (60, 3)) + [10, 0, 0]
    far = rng.uniform([-2, -0.8, -0.7], [2, 0.8, 0.7], (20, 3)) + [20, 0, 0]
    write_pcd(frames / "pcd" / f"{STAMP}.pcd", np.vstack([near, far, [[0, 0, 0]]]))
    predicted = {STAMP: [box_json(11, "Car", 10.1, 0.0), box_json(12, "Car", 20.1, 0.0)]}
    _, summary = evaluate(tmp_path, frames, predicted, "--min-points", "50")
    assert summary["per_frame"][STAMP]["points_in_truths"] == {"1": 60, "2": 20}
    assert counts(summary) == (1, 0, 0)
    assert summary["overall"]["predictions_ignored"] == 1


def test_min_points_needs_a_frames_folder(tmp_path, capsys):
    status, _ = evaluate(tmp_path, {STAMP: []}, {STAMP: []}, "--min-points", "50")
    assert status == 2
    assert "--min-points needs the clouds" in capsys.readouterr().err


def test_invalid_boxes_are_skipped_and_counted(tmp_path):
    nan_box = box_json(12, "Car", float("nan"), 0.0)
    flat_box = box_json(13, "Car", 5.0, 0.0, size=(4.0, 0.0, 1.5))
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0)]}
    _, summary = evaluate(tmp_path, truth, {STAMP: [box_json(11, "Car", 0, 0), nan_box,
                                                    flat_box]})
    assert summary["skipped_boxes"]["predicted"] == {
        "a box with NaN or infinite numbers": 1, "a box with a zero or negative size": 1}
    assert counts(summary) == (1, 0, 0)


# ---------------------------------------------------------------------------- report

def test_predictions_all_unknown_are_not_scored_by_class(tmp_path, capsys):
    # Geometric cuboids without a classifier: a class-aware 0.000 would read as all wrong.
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0), box_json(2, "Car", 10.0, 0.0)]}
    unknown = {STAMP: [box_json(11, "unknown", 0.0, 0.0), box_json(12, "unknown", 10.0, 0.0)]}
    cuboids.main(["--truth", str(write_frames(tmp_path / "truth", truth)), "--predicted",
                  str(write_frames(tmp_path / "unknown", unknown)), "--out",
                  str(tmp_path / "report")])
    printed = capsys.readouterr().out
    summary = json.loads((tmp_path / "report" / "summary.json").read_text())
    assert summary["overall"]["unclassified_predictions"] == 2
    assert "centre < 0.5 m, yaw < 10 deg       2     0     0  1.000  1.000  1.000               -" \
        in printed
    assert "class-aware: not scored, every prediction is unknown" in printed
    assert "| 2 | 0 | 0 | 1.000 | 1.000 | 1.000 | - | - | - | - |" in \
        (tmp_path / "report" / "index.md").read_text()
    # One named prediction is enough to score by class.
    named = {STAMP: [box_json(11, "Car", 0.0, 0.0), box_json(12, "unknown", 10.0, 0.0)]}
    _, summary = evaluate(tmp_path, truth, named)
    assert summary["overall"]["unclassified_predictions"] == 1
    assert counts(summary, kind="class_aware") == (1, 1, 1)


def test_report_has_the_summary_the_table_and_the_histograms(tmp_path):
    truth = {STAMP: [box_json(1, "Car", 0.0, 0.0), box_json(2, "Car", 10.0, 0.0)]}
    predicted = {STAMP: [box_json(11, "Car", 0.3, 0.0, yaw_deg=5)]}
    status, summary = evaluate(tmp_path, truth, predicted)
    assert status == 0
    report = tmp_path / "report"
    for name in ("centre_error.png", "yaw_error.png", "size_error.png", "iou.png"):
        assert (report / name).stat().st_size > 1000, name
    index = (report / "index.md").read_text()
    assert "| centre < 0.5 m, yaw < 10 deg | 1 | 0 | 1 | 1.000 | 0.500 | 0.667 |" in index
    assert "![yaw error](yaw_error.png)" in index
    assert set(summary["overall"]["errors"]) >= {"centre_3d_m", "yaw_deg", "length_m",
                                                 "width_m", "height_m"}
    assert (report / ".granular.json").exists()


def test_no_matched_pairs_still_gives_a_report(tmp_path):
    status, summary = evaluate(tmp_path, {STAMP: [box_json(1, "Car", 0.0, 0.0)]}, {STAMP: []})
    assert status == 0
    assert summary["overall"]["errors"]["yaw_deg"]["median"] is None
    assert (tmp_path / "report" / "yaw_error.png").exists()


# ---------------------------------------------------------------------------- tracking

def drive(frames):
    """{stamp: boxes} of frames 0.1 s apart from a list of box lists."""
    return {str(1586102742000000000 + 100000000 * k): boxes for k, boxes in enumerate(frames)}


def test_tracking_counts_misses_false_positives_and_identity_switches(tmp_path):
    # Vehicle 1 is followed by track 7, then by track 8 (a switch); vehicle 2 by track 9,
    # missed in frame 4; frame 5 holds a false track far from both. 12 truths, 11 followed.
    truth, predicted = [], []
    for k in range(6):
        truth.append([box_json(1, "Sedan", 10.0 + k, 0.0), box_json(2, "SUV", -10.0, 5.0)])
        boxes = [box_json(7 if k < 3 else 8, "Sedan", 10.1 + k, 0.0)]
        boxes += [box_json(9, "SUV", -10.0, 5.2)] if k != 4 else []
        boxes += [box_json(10, "Jeep", 30.0, 30.0)] if k == 5 else []
        predicted.append(boxes)
    status, summary = evaluate(tmp_path, drive(truth), drive(predicted), "--tracking")
    assert status == 0
    tracking = summary["tracking"]
    assert (tracking["truths"], tracking["tp"], tracking["fp"], tracking["fn"],
            tracking["id_switches"]) == (12, 11, 1, 1, 1)
    assert tracking["mota"] == pytest.approx(1 - 3 / 12)
    assert tracking["id_switches_per_100_track_frames"] == pytest.approx(100 / 11)
    assert (tracking["vehicles_followed"], tracking["tracks_following"]) == (2, 3)
    index = (tmp_path / "report" / "index.md").read_text()
    assert "| 0.750 | 11 | 1 | 1 | 1 | 9.09 | 2 | 3 |" in index


def test_a_track_back_on_its_vehicle_is_a_second_switch_and_misfits_are_no_correspondence(
        tmp_path):
    # Vehicle 1: tracks 7, 8, 7 (two switches); in frame 3 track 7 is 0.8 m off (beyond the
    # paper's 0.5 m): a miss and a false positive, and no switch.
    truth = [[box_json(1, "Sedan", 10.0 + k, 0.0)] for k in range(4)]
    predicted = [[box_json(7, "Sedan", 10.0, 0.0)], [box_json(8, "Sedan", 11.0, 0.0)],
                 [box_json(7, "Sedan", 12.0, 0.0)], [box_json(7, "Sedan", 13.8, 0.0)]]
    status, summary = evaluate(tmp_path, drive(truth), drive(predicted), "--tracking")
    assert status == 0
    tracking = summary["tracking"]
    assert (tracking["tp"], tracking["fp"], tracking["fn"], tracking["id_switches"]) == \
        (3, 1, 1, 2)
    assert tracking["mota"] == pytest.approx(1 - 4 / 4)


def test_a_track_settles_on_its_class_from_the_frame_its_label_stays_right(tmp_path):
    # Track 7 says unknown, SUV, Sedan, Sedan of a Sedan: settled from its third frame. Track 8
    # ends on a wrong label: never settled. Without --tracking there is no tracking section.
    labels_7 = ["unknown", "SUV", "Sedan", "Sedan"]
    labels_8 = ["Jeep", "Jeep", "Jeep", "SUV"]
    truth = [[box_json(1, "Sedan", 10.0, 0.0), box_json(2, "Jeep", 0.0, 10.0)]
             for _ in range(4)]
    predicted = [[box_json(7, labels_7[k], 10.0, 0.0), box_json(8, labels_8[k], 0.0, 10.0)]
                 for k in range(4)]
    status, summary = evaluate(tmp_path, drive(truth), drive(predicted), "--tracking")
    assert status == 0
    tracking = summary["tracking"]
    assert tracking["class_settled_tracks"] == 1
    assert tracking["frames_to_settle"]["median"] == 3
    assert tracking["mota"] == 1.0
    status, summary = evaluate(tmp_path, drive(truth), drive(predicted))
    assert status == 0 and "tracking" not in summary


# ---------------------------------------------------------------------------- bad input

def run_script(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, timeout=120)


def test_missing_folder_and_invalid_json_are_one_line_errors(tmp_path):
    result = run_script("--truth", tmp_path / "nowhere", "--predicted", tmp_path,
                        "--out", tmp_path / "report")
    assert result.returncode == 1
    assert result.stderr.strip() == \
        f"evaluate_cuboids: error: {tmp_path / 'nowhere'}: truth folder does not exist"
    truth = write_frames(tmp_path / "truth", {STAMP: [box_json(1, "Car", 0, 0)]})
    (truth / f"{OTHER_STAMP}.json").write_text('{"detections": [')
    result = run_script("--truth", truth, "--predicted", truth, "--out", tmp_path / "report",
                        "--quiet")
    assert result.returncode == 1 and "Traceback" not in result.stderr
    assert f"{truth / OTHER_STAMP}.json: not valid JSON" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "report").exists()
    # Nested past Python's recursion limit: a RecursionError traceback before.
    (truth / f"{OTHER_STAMP}.json").write_text("[" * 100_000)
    result = run_script("--truth", truth, "--predicted", truth, "--out", tmp_path / "report",
                        "--quiet")
    assert result.returncode == 1 and "Traceback" not in result.stderr
    assert f"{truth / OTHER_STAMP}.json: not a detections file" in result.stderr


def test_a_malformed_box_names_the_file_and_the_key(tmp_path, capsys):
    box = box_json(1, "Car", 0, 0)
    del box["bbox"]["size"]["z"]
    status, _ = evaluate(tmp_path, {STAMP: [box]}, {STAMP: []})
    assert status == 1
    err = capsys.readouterr().err
    assert f"{STAMP}.json: detections[0].bbox.size.z: missing" in err


def test_output_folders_are_safe(tmp_path, capsys):
    truth = write_frames(tmp_path / "truth", {STAMP: [box_json(1, "Car", 0, 0)]})
    out = tmp_path / "report"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    args = ["--truth", str(truth), "--predicted", str(truth), "--out", str(out), "--quiet"]
    assert cuboids.main(args + ["--overwrite"]) == 1
    assert "holds files that no granular tool wrote" in capsys.readouterr().err
    assert [p.name for p in out.iterdir()] == ["notes.txt"]
    out2 = tmp_path / "report2"
    assert cuboids.main(args[:-2] + [str(out2), "--quiet"]) == 0
    assert cuboids.main(args[:-2] + [str(out2), "--quiet"]) == 1
    assert "pass --overwrite to replace them" in capsys.readouterr().err
    assert cuboids.main(args[:-2] + [str(out2), "--quiet", "--overwrite"]) == 0
    # The report may not replace an input.
    assert cuboids.main(["--truth", str(truth), "--predicted", str(truth), "--out", str(truth),
                         "--overwrite", "--quiet"]) == 2
    assert "would replace the input" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report", "report2", "truth"]


def test_bad_options_exit_2_and_help_tells_the_criteria(tmp_path):
    result = run_script("--truth", tmp_path, "--predicted", tmp_path, "--out", tmp_path / "r",
                        "--max-range", "-5")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "--max-range: must be a positive number of metres" in result.stderr
    result = run_script("--help")
    assert result.returncode == 0
    for words in ("Hungarian", "modulo 180", "3-D IoU", "--class-map", "--min-points",
                  "don't care"):
        assert words in " ".join(result.stdout.split()), words
