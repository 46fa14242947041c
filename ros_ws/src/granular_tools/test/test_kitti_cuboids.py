"""Cuboids on the real KITTI frames of ../shared/fixtures/kitti: fit_cuboids, from the given
boxes and from the box-free segments, scored by evaluate_cuboids against KITTI's labelled cars
of at least 50 points (docs/cuboids.md, "What they measured")."""
import json
import pathlib
import subprocess

from granular_tools.evaluation import cuboids as evaluate_cuboids
from granular_tools.runners.stages import without_rosrun

REPO_ROOT = pathlib.Path(__file__).resolve().parents[4]
FIT_CUBOIDS = without_rosrun(["rosrun", "granular_ros", "fit_cuboids"])
# KITTI's HDL-64E and KITTI's size priors, as scripts/bench_cuboids runs them.
KITTI_OPTIONS = ["--config", str(REPO_ROOT / "config" / "cuboids.yaml"), "--method", "geometric",
                 "--prior-classes", "Car,Van,Truck", "--sensor-height", "1.73",
                 "--azimuth-step", "0.176"]


def scored(frames, boxes, folder, scoring=()):
    """The overall figures of evaluate_cuboids for cuboids fitted to `boxes` (into `folder`),
    `scoring` added to evaluate_cuboids' options."""
    fitted, report = folder / "fitted", folder / "report"
    run = subprocess.run(FIT_CUBOIDS + ["--frames", str(frames), "--out", str(fitted),
                                        "--boxes", boxes] + KITTI_OPTIONS,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert evaluate_cuboids.main(["--truth", str(frames), "--predicted", str(fitted),
                                  "--out", str(report), "--min-points", "50", "--labels", "Car",
                                  "--quiet", *scoring]) == 0
    return json.loads((report / "summary.json").read_text())["overall"]


def test_fitting_the_given_boxes_meets_the_yaw_and_centre_targets(kitti_frames, tmp_path):
    overall = scored(kitti_frames, "detections", tmp_path)
    assert overall["truths"] == 13
    assert overall["errors"]["yaw_deg"]["median"] <= 5.0
    assert overall["errors"]["centre_3d_m"]["median"] <= 0.25


def test_cuboids_from_segments_find_eleven_of_the_thirteen_cars(kitti_frames, tmp_path):
    """Within 0.5 m and 10 degrees (the paper's criterion). The two missed: a car seen end on,
    whose length no return tells, and one whose few returns show its front at 34 degrees to
    its labelled heading; the car beside a hedge (frame 000002) is found since low cells link
    nothing (segmentation.yaml, objects.link_min_top)."""
    overall = scored(kitti_frames, "segment", tmp_path)
    assert overall["truths"] == 13
    assert overall["criteria"]["paper"]["tp"] >= 11


def test_the_zero_shot_vehicle_decision_keeps_the_cars_and_little_else(kitti_frames, tmp_path):
    """Issue 47's target in the camera's view (40 degrees either side), no KITTI label used:
    precision and recall at least 0.80. The hedge line of frame 000000, 7 m long and 2.3 m
    tall behind parked cars, passed as a truck before min_long_top (test_vehicle_evidence)."""
    overall = scored(kitti_frames, "segment", tmp_path, ["--field-of-view", "40"])
    paper = overall["criteria"]["paper"]
    assert overall["truths"] == 13
    assert paper["precision"] >= 0.80, paper
    assert paper["recall"] >= 0.80, paper
