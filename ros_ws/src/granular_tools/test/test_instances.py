"""Scores over instances: the bootstrap resamples vehicles, not objects; one vote per track; the
four cars on their own; and the report's table and summary with them."""
import json

import pytest

from granular_tools.evaluation import report
from granular_tools.evaluation.instances import (bootstrap_interval, instance_scores,
                                                 instances_of, track_vote)
from granular_tools.evaluation.metrics import ResultsError


def test_all_correct_has_no_spread():
    assert bootstrap_interval([[1, 1, 1], [1]]) == (1.0, 1.0)


def test_two_vehicles_seen_often_leave_the_accuracy_wide_open():
    # 100 frames of a car always right and 100 of one always wrong: 200 objects, but two
    # vehicles. Resampling objects would give about 0.43-0.57; resampling the two vehicles
    # gives every mixture, both ends included.
    assert bootstrap_interval([[1] * 100, [0] * 100]) == (0.0, 1.0)


def test_many_vehicles_narrow_the_interval_around_the_accuracy():
    groups = [[1, 1, 1, 1]] * 80 + [[0, 0, 0, 0]] * 20
    low, high = bootstrap_interval(groups)
    assert low < 0.8 < high
    assert high - low < 0.2  # binomial: 2 * 1.96 * sqrt(0.8 * 0.2 / 100) = 0.157
    assert bootstrap_interval(groups, seed=1) != (low, high)  # the seed is used ...
    assert bootstrap_interval(groups) == (low, high)  # ... and fixes the result


def test_a_track_votes_once_and_a_tie_does_not_decide():
    assert track_vote("Sedan", ["Sedan", "Sedan", "Hatchback"])
    assert not track_vote("Sedan", ["Hatchback", "Hatchback", "Sedan"])
    assert not track_vote("Sedan", ["Sedan", "Hatchback"])
    assert not track_vote("Sedan", [None, None, "Sedan"])


def records(rows):
    return [{"file": f"{t}-{i}.pcd", "true_label": t, "predictions": {"criterion2": p}}
            for i, (t, p) in enumerate(rows)]


ROWS = [("Sedan", "Sedan")] * 3 + [("Sedan", "Hatchback")] + \
    [("Hatchback", "Sedan")] * 2 + [("Hatchback", "Hatchback")] + [("BoxTruck", "BoxTruck")] * 2
# Instances: the Sedan 7 (3 right, 1 wrong), the Hatchback 8 (1 of 3), the BoxTruck 9 (2 of 2).
INSTANCES = {f"{t}-{i}.pcd": f"{t}#{ {'Sedan': 7, 'Hatchback': 8, 'BoxTruck': 9}[t] }"
             for i, (t, _) in enumerate(ROWS)}


def test_instance_scores_against_hand_counts():
    scores = instance_scores(records(ROWS), INSTANCES, "criterion2")
    assert scores["instances"] == 3 and scores["objects"] == 9
    assert scores["accuracy"] == pytest.approx(6 / 9)
    assert scores["per_track"] == pytest.approx(2 / 3)  # the Hatchback's vote is Sedan
    cars = instance_scores(records(ROWS), INSTANCES, "criterion2", ("Sedan", "Hatchback"))
    assert (cars["instances"], cars["objects"]) == (2, 7)
    assert cars["accuracy"] == pytest.approx(4 / 7)
    assert cars["per_track"] == pytest.approx(1 / 2)
    assert instance_scores(records(ROWS), INSTANCES, "criterion2", ("Jeep",)) is None


def test_an_object_missing_from_the_index_is_named():
    with pytest.raises(ResultsError, match="Sedan-0.pcd"):
        instance_scores(records(ROWS), {}, "criterion2")


def write_index(folder, rows):
    folder.mkdir(parents=True)
    lines = ["file,label,detection_id,stamp,points"] + [
        f"{name},{name.split('-')[0]},{key.split('#')[1]},1,50" for name, key in rows.items()]
    (folder / "index.csv").write_text("\n".join(lines) + "\n")


def test_the_index_gives_label_and_detection_id(tmp_path):
    write_index(tmp_path / "N10", INSTANCES)
    assert instances_of(tmp_path / "N10") == INSTANCES
    with pytest.raises(ResultsError, match="index.csv"):
        instances_of(tmp_path / "absent")


def test_the_report_shows_the_intervals_and_tracks(tmp_path):
    results = tmp_path / "results" / "icp_tuned" / "N10.json"
    results.parent.mkdir(parents=True)
    results.write_text(json.dumps({"objects": records(ROWS)}))
    write_index(tmp_path / "objects" / "N10", INSTANCES)
    assert report.main(["--results", str(tmp_path / "results"), "--out", str(tmp_path / "report"),
                        "--objects", str(tmp_path / "objects")]) == 0
    entry = json.loads((tmp_path / "report" / "summary.json").read_text())[
        "methods"]["icp_tuned"]["N10"]["instances"]
    assert entry["all"]["accuracy"] == pytest.approx(6 / 9)
    assert entry["four_cars"]["per_track"] == pytest.approx(1 / 2)
    low, high = entry["all"]["interval"]
    assert 0.0 <= low < 6 / 9 < high <= 1.0
    index = (tmp_path / "report" / "index.md").read_text()
    assert f"| icp_tuned | 10 | 3 | 0.667 [{low:.3f}, {high:.3f}] | 0.667 [" in index
