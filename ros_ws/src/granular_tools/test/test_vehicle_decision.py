"""train_vehicle_decision (the few-shot vehicle decision) on the real KITTI frames of
../shared/fixtures/kitti: tuned on five labelled frames, the file it writes is what
fit_cuboids --classifier takes, and it scores on those frames what the tool said it would
(docs/cuboids.md, "Few-shot")."""
import json
import pathlib
import re
import subprocess

import yaml

from granular_tools.evaluation import cuboids as evaluate_cuboids
from granular_tools.runners import vehicle_decision
from granular_tools.runners.stages import without_rosrun

FIT_CUBOIDS = without_rosrun(["rosrun", "granular_ros", "fit_cuboids"])
KITTI_SENSOR = ["--sensor", "hdl64e", "--prior-classes", "Car,Van,Truck"]
SCORING = ["--labels", "Car", "--field-of-view", "40"]


def last_five(kitti_frames, folder):
    """A frames folder of the fixture's last five frames (links), the five holding ten of its
    thirteen cars of at least 50 points."""
    stamps = sorted(path.stem for path in (kitti_frames / "pcd").glob("*.pcd"))[5:]
    for sub, suffix in (("pcd", ".pcd"), ("detections_3d", ".json")):
        (folder / sub).mkdir(parents=True)
        for stamp in stamps:
            (folder / sub / (stamp + suffix)).symlink_to(kitti_frames / sub / (stamp + suffix))
    return folder


def paper_score(frames, decision, folder):
    fitted, report = folder / "fitted", folder / "report"
    run = subprocess.run(FIT_CUBOIDS + ["--frames", str(frames), "--out", str(fitted), "--boxes",
                                        "segment", "--classifier", str(decision)] + KITTI_SENSOR,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert evaluate_cuboids.main(["--truth", str(frames), "--predicted", str(fitted), "--out",
                                  str(report), "--min-points", "50", "--quiet"] + SCORING) == 0
    return json.loads((report / "summary.json").read_text())["overall"]["criteria"]["paper"]


def test_a_decision_tuned_on_five_frames_scores_what_it_claims(kitti_frames, tmp_path, capsys):
    frames = last_five(kitti_frames, tmp_path / "frames")
    decision = tmp_path / "decision.yaml"
    assert vehicle_decision.main(["--frames", str(frames), "--out", str(decision), "--quiet"]
                                 + KITTI_SENSOR + SCORING) == 0
    said = capsys.readouterr().out
    zero_shot, tuned = (float(value) for value in
                        re.search(r"zero-shot ([0-9.]+), tuned ([0-9.]+)", said).groups())
    assert tuned >= zero_shot
    evidence = yaml.safe_load(decision.read_text())["evidence"]
    assert set(evidence) <= set(vehicle_decision.TUNED) | {"min_body_points"}
    paper = paper_score(frames, decision, tmp_path)
    assert round(paper["f1"], 3) == tuned, (said, paper)


def test_refuses_frames_without_labels_and_an_existing_output(tmp_path, capsys):
    (tmp_path / "frames" / "pcd").mkdir(parents=True)
    status = vehicle_decision.main(["--frames", str(tmp_path / "frames"), "--out",
                                    str(tmp_path / "d.yaml"), "--labels", "Car"])
    assert status == 2
    assert "holds no detections_3d/" in capsys.readouterr().err
    existing = tmp_path / "d.yaml"
    existing.write_text("mine\n")
    (tmp_path / "frames" / "detections_3d").mkdir()
    status = vehicle_decision.main(["--frames", str(tmp_path / "frames"), "--out",
                                    str(existing), "--labels", "Car"])
    assert status == 2
    assert "exists (--overwrite replaces it)" in capsys.readouterr().err
    assert existing.read_text() == "mine\n"


def test_fit_cuboids_names_an_unknown_key_of_a_decision(kitti_frames, tmp_path):
    decision = tmp_path / "decision.yaml"
    decision.write_text("evidence:\n  min_pointz: 45\n")
    run = subprocess.run(FIT_CUBOIDS + ["--frames", str(kitti_frames), "--out",
                                        str(tmp_path / "fitted"), "--boxes", "segment",
                                        "--classifier", str(decision)] + KITTI_SENSOR,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2
    assert "evidence.min_pointz: unknown key" in run.stderr
    assert not (tmp_path / "fitted").exists()
