"""evaluate_many: the mean over drive pairs and its interval resample each pair on its own; the
pooled numbers are the pairs' own reports'; a finished pair is reused; bad pairs are refused."""
import json

import pytest

import hostile
from granular_tools.evaluation.instances import mean_interval
from granular_tools.runners.many import check_seeds, parse_pairs, train_seeds

EVALUATE_MANY = hostile.tool("granular_tools", "evaluate_many")


def test_the_mean_over_pairs_varies_only_within_each_pair():
    # One pair always right, one always wrong: every resample keeps each pair's accuracy, so
    # the mean is 0.5 in all of them. Pooling the instances would give any mixture instead.
    assert mean_interval([[[1] * 10] * 5, [[0] * 10] * 5]) == (0.5, 0.5)
    low, high = mean_interval([[[1], [0]] * 20, [[1], [1], [1], [0]] * 10])
    assert low < (0.5 + 0.75) / 2 < high


def test_pairs_are_train_and_test_seeds():
    assert parse_pairs("1:2, 101:202") == [(1, 2), (101, 202)]
    for bad in ("1", "1:1", "a:b", "", "1:2:3"):
        with pytest.raises(ValueError, match="--pairs"):
            parse_pairs(bad)


def test_two_short_pairs_pool_their_own_reports(tmp_path):
    out = tmp_path / "many"
    arguments = EVALUATE_MANY + ["--out", out, "--pairs", "1:2,3:4", "--duration", "8",
                                 "--train-drives", "1", "--methods", "icp", "--supervised",
                                 "knn", "--n-thresh", "10"]
    result = hostile.run(arguments)
    assert result.status == 0, str(result)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["pairs"] == [[1, 2], [3, 4]]
    for method in ("icp_tuned", "knn"):
        pooled = summary["methods"][method]["N10"]["all"]
        own = [json.loads((out / f"pair-{a}-{b}" / "evaluation" / "report" / "summary.json")
                          .read_text())["methods"][method]["N10"] for a, b in ((1, 2), (3, 4))]
        assert pooled["per_pair"] == pytest.approx([r["accuracy"] for r in own])
        assert pooled["mean"] == pytest.approx(sum(pooled["per_pair"]) / 2)
        assert pooled["instances"] == sum(r["instances"]["all"]["instances"] for r in own)
        assert pooled["interval"][0] <= pooled["mean"] <= pooled["interval"][1]
        cars = summary["methods"][method]["N10"]["four_cars"]
        assert cars["per_pair"] == pytest.approx(
            [r["instances"]["four_cars"]["accuracy"] for r in own])
    index = (out / "index.md").read_text()
    assert f"| knn | 10 | {summary['methods']['knn']['N10']['all']['instances']} |" in index

    again = hostile.run(arguments)  # both pairs are complete: nothing is run again
    assert again.status == 0, str(again)
    assert again.stdout.count("reusing") == 2
    assert json.loads((out / "summary.json").read_text()) == summary


def test_a_pairs_further_train_drives_never_share_a_seed_with_a_test_drive():
    assert train_seeds((1, 2), 3) == [1, 1001, 2001]
    check_seeds([(1, 2), (101, 202)], 3)
    with pytest.raises(ValueError, match="test seed 1001 is also a train drive's"):
        check_seeds([(1, 2), (5, 1001)], 2)
    check_seeds([(1, 2), (5, 1001)], 1)


def test_bad_pairs_are_refused_before_anything_runs(tmp_path):
    result = hostile.run(EVALUATE_MANY + ["--out", tmp_path / "many", "--pairs", "5:5"])
    assert result.status == 2
    assert "must not be the train drive" in result.stderr
    assert not (tmp_path / "many").exists()
