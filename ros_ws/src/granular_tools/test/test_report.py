"""make_report: numbers against hand-computed values, pictures, and bad input."""
import json
import os
import signal

import pytest

from granular_tools import output
from granular_tools.evaluation import report

SEDAN_HATCHBACK = [  # (true label, criterion 1, criterion 2)
    ("Sedan", "Sedan", "Sedan"), ("Sedan", None, "Sedan"), ("Sedan", None, "Hatchback"),
    ("Sedan", None, None), ("Hatchback", "Hatchback", "Hatchback"), ("Hatchback", None, "Sedan"),
]


def write_results(folder, method, threshold, rows, seconds=1.5):
    path = folder / method / f"N{threshold}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    objects = [{"file": f"{t}-1-{i}.pcd", "true_label": t,
                "predictions": {"criterion1": c1, "criterion2": c2}}
               for i, (t, c1, c2) in enumerate(rows)]
    path.write_text(json.dumps({"method": method, "seconds": seconds, "objects": objects}))


def test_summary_numbers_match_hand_computed_values(tmp_path):
    write_results(tmp_path / "results", "icp", 10, SEDAN_HATCHBACK)
    write_results(tmp_path / "results", "icp", 300, SEDAN_HATCHBACK[:1] + SEDAN_HATCHBACK[4:5])
    assert report.main(["--results", str(tmp_path / "results"),
                        "--out", str(tmp_path / "report")]) == 0
    summary = json.loads((tmp_path / "report" / "summary.json").read_text())
    assert summary["classes"] == ["Sedan", "Hatchback"]
    entry = summary["methods"]["icp"]["N10"]
    assert entry["primary"] == "criterion2"
    assert entry["objects"] == 6
    assert entry["accuracy"] == pytest.approx(3 / 6)
    assert entry["coverage"] == pytest.approx(5 / 6)
    assert entry["missing"] == {"criterion1": 4, "criterion2": 1}
    assert entry["per_class"]["Sedan"] == pytest.approx(
        {"precision": 2 / 3, "recall": 2 / 4, "support": 4})
    assert entry["per_class"]["Hatchback"] == pytest.approx(
        {"precision": 1 / 2, "recall": 1 / 2, "support": 2})
    sedan_f1, hatchback_f1 = 2 * (2 / 3 * 0.5) / (2 / 3 + 0.5), 0.5
    assert entry["macro_f1"] == pytest.approx((sedan_f1 + hatchback_f1) / 2)
    assert entry["by_prediction"]["criterion1"]["accuracy"] == pytest.approx(2 / 6)
    assert entry["seconds"] == 1.5
    assert summary["methods"]["icp"]["N300"]["accuracy"] == 1.0


def test_report_has_every_picture_and_an_index(tmp_path):
    write_results(tmp_path / "results", "icp", 10, SEDAN_HATCHBACK)
    write_results(tmp_path / "results", "knn", 10, SEDAN_HATCHBACK)
    pictures = tmp_path / "models" / "pictures"
    pictures.mkdir(parents=True)
    (pictures / "overview.png").write_bytes(b"png")
    assert report.main(["--results", str(tmp_path / "results"), "--out",
                        str(tmp_path / "report"), "--model-pictures", str(pictures)]) == 0
    out = tmp_path / "report"
    for name in ("accuracy.png", "confusion/icp-N10.png", "confusion/knn-N10.png",
                 "precision_recall/icp.png", "precision_recall/knn.png"):
        assert (out / name).stat().st_size > 1000, name
    index = (out / "index.md").read_text()
    assert "| icp | 10 | 6 | 0.500 |" in index
    assert "(confusion/knn-N10.png)" in index and "../models/pictures/overview.png" in index


def test_missing_or_malformed_results_are_errors_and_nothing_is_written(tmp_path, capsys):
    (tmp_path / "results").mkdir()
    assert report.main(["--results", str(tmp_path / "results"),
                        "--out", str(tmp_path / "report")]) == 1
    assert "no <method>/N<thresh>.json" in capsys.readouterr().err
    (tmp_path / "results" / "icp").mkdir()
    (tmp_path / "results" / "icp" / "N10.json").write_text("{not json")
    assert report.main(["--results", str(tmp_path / "results"),
                        "--out", str(tmp_path / "report")]) == 1
    assert "N10.json: not a classification results file" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results"]


def test_a_report_is_replaced_only_with_overwrite(tmp_path, capsys):
    write_results(tmp_path / "results", "icp", 10, SEDAN_HATCHBACK)
    arguments = ["--results", str(tmp_path / "results"), "--out", str(tmp_path / "report")]
    assert report.main(arguments) == 0
    (tmp_path / "report" / "index.md").write_text("annotated by hand")
    assert report.main(arguments) == 1
    assert "--overwrite" in capsys.readouterr().err
    assert (tmp_path / "report" / "index.md").read_text() == "annotated by hand"
    assert report.main(arguments + ["--overwrite"]) == 0
    assert "| icp | 10 | 6 | 0.500 |" in (tmp_path / "report" / "index.md").read_text()


def test_a_folder_that_is_not_a_report_is_not_replaced(tmp_path, capsys):
    write_results(tmp_path / "results", "icp", 10, SEDAN_HATCHBACK)
    (tmp_path / "precious").mkdir()
    (tmp_path / "precious" / "notes.txt").write_text("keep me")
    assert report.main(["--results", str(tmp_path / "results"),
                        "--out", str(tmp_path / "precious")]) == 1
    assert (tmp_path / "precious" / "notes.txt").exists()


def _record_handlers(folder):
    handlers = {signal.Signals(n).name: signal.getsignal(n) == signal.SIG_DFL
                for n in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    (folder / f"{os.getpid()}.json").write_text(json.dumps(handlers))


def test_picture_workers_die_on_a_stop_signal_instead_of_running_the_tools_handler(tmp_path):
    # The tool's handlers raise on a signal; forked workers that kept them could hang the pool
    # when it terminates them. Each worker must have the default (die at once) instead.
    if (os.cpu_count() or 1) < 2:
        pytest.skip("one core: the pictures are drawn without workers")
    previous = {n: signal.getsignal(n) for n in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    output.stop_on_signals()
    try:
        report.draw_pictures([(_record_handlers, (tmp_path,)) for _ in range(6)])
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    records = [json.loads(p.read_text()) for p in tmp_path.glob("*.json")]
    assert records and all(all(r.values()) for r in records), records
    assert str(os.getpid()) + ".json" not in {p.name for p in tmp_path.glob("*.json")}
