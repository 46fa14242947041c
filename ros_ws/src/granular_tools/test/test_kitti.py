"""kitti_to_bag: KITTI boxes in the LiDAR frame hold the points KITTI's own frame puts in them;
labels survive a round trip; bad input stops the run with the file named and no bag left."""
import argparse
import math
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest
import rosbag

from granular_tools import kitti
from granular_tools.bag_to_files import offline
from granular_tools.geometry import count_points_inside, quaternion_from_matrix, rotation_matrix
from granular_tools.messages import cloud_xyz, detection_cuboid

SCRIPT = pathlib.Path(__file__).resolve().parents[1] / "scripts" / "kitti_to_bag"
START = 1586102742.0

# The fixture README's oracle: LiDAR points inside each labelled box, counted in the rectified
# camera frame with KITTI's own R0_rect * Tr_velo_to_cam. (frame, label line, class, points)
ORACLE = [
    (0, 0, "Pedestrian", 376),
    (1, 0, "Truck", 70), (1, 1, "Car", 9), (1, 2, "Cyclist", 18),
    (2, 0, "Misc", 1351), (2, 1, "Car", 67),
    (3, 0, "Car", 680),
    (4, 0, "Car", 77), (4, 1, "Car", 26),
    (5, 0, "Pedestrian", 70),
    (6, 0, "Car", 9), (6, 1, "Car", 71), (6, 2, "Car", 331), (6, 3, "Car", 26),
    (7, 0, "Car", 191), (7, 1, "Car", 19), (7, 2, "Car", 5), (7, 3, "Cyclist", 25),
    (8, 0, "Car", 6237), (8, 1, "Car", 1940), (8, 2, "Car", 1041), (8, 3, "Car", 668),
    (8, 4, "Car", 53), (8, 5, "Car", 164),
    (9, 0, "Car", 219), (9, 1, "Car", 4), (9, 2, "Car", 1),
]
EXPECTED = {frame * 1000 + line: (label, points) for frame, line, label, points in ORACLE}


def read_bag(path):
    """{topic: [message]} in recording order."""
    messages = {}
    with rosbag.Bag(str(path)) as bag:
        for topic, message, _ in bag.read_messages():
            messages.setdefault(topic, []).append(message)
    return messages


def frames(kitti_fixture):
    for frame in range(10):
        stem = f"{frame:06d}"
        yield (stem, kitti.read_calib(kitti_fixture / "calib" / f"{stem}.txt"),
               kitti.read_labels(kitti_fixture / "label_2" / f"{stem}.txt"))


def small_kitti(kitti_fixture, folder, stems=("000000", "000001")):
    """A KITTI folder of a few fixture frames (clouds linked, text files copied to be edited)."""
    for sub in ("velodyne", "label_2", "calib"):
        (folder / sub).mkdir(parents=True)
    for stem in stems:
        os.symlink(kitti_fixture / "velodyne" / f"{stem}.bin", folder / "velodyne" / f"{stem}.bin")
        for sub in ("label_2", "calib"):
            shutil.copy(kitti_fixture / sub / f"{stem}.txt", folder / sub / f"{stem}.txt")
    return folder


def assert_nothing_written(folder):
    assert [p.name for p in folder.iterdir()] == ["kitti"], "a bag or a partial one was left"


# --- The headline: boxes hold exactly the oracle's points --------------------------------------

def test_every_labelled_box_in_the_bag_holds_exactly_the_oracles_points(kitti_bag):
    messages = read_bag(kitti_bag)
    counted = {}
    for cloud, detections in zip(messages[kitti.CLOUD_TOPIC],
                                 messages[kitti.DETECTIONS_TOPIC], strict=True):
        assert cloud.header.stamp == detections.header.stamp
        xyz = cloud_xyz(cloud)
        for detection in detections.detections:
            counted[detection.id] = (detection.label,
                                     count_points_inside(xyz, detection_cuboid(detection)))
    assert counted == EXPECTED


def test_extract_objects_crops_exactly_the_oracles_points_from_the_bag(kitti_bag, tmp_path):
    """bag_to_files, then the C++ extraction (float32 points, float64 boxes from JSON)."""
    frames_folder, objects = tmp_path / "frames", tmp_path / "objects"
    assert offline.main(["--bag", str(kitti_bag), "--out", str(frames_folder), "--quiet"]) == 0
    try:
        extracted = subprocess.run(
            ["rosrun", "granular_ros", "extract_objects", "--in", str(frames_folder), "--out",
             str(objects), "--n-thresh", "1"], capture_output=True, text=True, timeout=120)
    except FileNotFoundError:
        pytest.skip("rosrun is not on PATH")
    if "Couldn't find executable" in extracted.stderr:
        pytest.skip("granular_ros extract_objects is not built")
    assert extracted.returncode == 0, extracted.stderr
    rows = (objects / "index.csv").read_text().splitlines()
    header = rows[0].split(",")
    counted = {}
    for row in rows[1:]:
        values = dict(zip(header, row.split(",")))
        counted[int(values["detection_id"])] = (values["label"], int(values["points"]))
    assert counted == EXPECTED


# --- The bag's layout ---------------------------------------------------------------------------

def test_bag_has_the_simulators_layout_stamps_and_points(kitti_bag, kitti_fixture):
    messages = read_bag(kitti_bag)
    assert sorted(messages) == [kitti.DETECTIONS_TOPIC, kitti.CLOUD_TOPIC]
    clouds = messages[kitti.CLOUD_TOPIC]
    assert len(clouds) == 10
    for k, cloud in enumerate(clouds):
        assert cloud.header.stamp.to_nsec() == int(START * 1e9) + k * 100_000_000
        assert cloud.header.frame_id == "velodyne"
        assert [(f.name, f.offset, f.datatype) for f in cloud.fields] == [
            ("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("intensity", 16, 2), ("timestamp", 24, 8)]
        points = np.frombuffer(cloud.data, dtype=kitti_point_dtype())
        raw = kitti.read_velodyne(kitti_fixture / "velodyne" / f"{k:06d}.bin")
        assert cloud.width == len(raw) and cloud.height == 1
        np.testing.assert_array_equal(np.stack([points[a] for a in "xyz"], 1), raw[:, :3])
        np.testing.assert_array_equal(points["intensity"],
                                      np.rint(raw[:, 3].astype(float) * 255).astype(np.uint8))
        assert np.all(points["timestamp"] == cloud.header.stamp.to_sec())
    for detections in messages[kitti.DETECTIONS_TOPIC]:
        for detection in detections.detections:
            assert detection.header.frame_id == "velodyne" and detection.score == 1.0
            q = detection.bbox.position.orientation
            assert math.isclose(math.hypot(q.x, q.y, q.z, q.w), 1.0, abs_tol=1e-12)


def kitti_point_dtype():
    from granular_tools.messages import POINT_DTYPE
    return POINT_DTYPE


def test_reflectance_maps_to_intensity_0_to_255_rounded_and_clamped():
    np.testing.assert_array_equal(
        kitti.intensity_of(np.array([0.0, 0.5, 1.0, 0.001, 0.999, 1.5, -0.1, np.nan])),
        [0, 128, 255, 0, 255, 255, 0, 0])


def test_frames_start_time_and_frame_id_options(kitti_fixture, tmp_path):
    bag = tmp_path / "some.bag"
    assert kitti.main([str(kitti_fixture), "--out", str(bag), "--frames", "000003-000004,8",
                       "--start-time", "100.05", "--frame-id", "lidar", "--quiet"]) == 0
    messages = read_bag(bag)
    stamps = [m.header.stamp.to_nsec() for m in messages[kitti.CLOUD_TOPIC]]
    assert stamps == [100_050_000_000, 100_150_000_000, 100_250_000_000]
    ids = [d.id for m in messages[kitti.DETECTIONS_TOPIC] for d in m.detections]
    assert ids == [3000, 4000, 4001, 8000, 8001, 8002, 8003, 8004, 8005]
    assert {m.header.frame_id for m in messages[kitti.CLOUD_TOPIC]} == {"lidar"}


def test_no_boxes_gives_a_bag_with_only_the_cloud_topic(kitti_fixture, tmp_path):
    bag = tmp_path / "clouds.bag"
    assert kitti.main([str(kitti_fixture), "--out", str(bag), "--no-boxes", "--frames", "0,1",
                       "--quiet"]) == 0
    with rosbag.Bag(str(bag)) as opened:
        topics = opened.get_type_and_topic_info().topics
    assert {t: i.message_count for t, i in topics.items()} == {kitti.CLOUD_TOPIC: 2}


def test_no_boxes_needs_neither_labels_nor_calib(kitti_fixture, tmp_path):
    folder = small_kitti(kitti_fixture, tmp_path / "kitti")
    shutil.rmtree(folder / "label_2")
    shutil.rmtree(folder / "calib")
    assert kitti.main([str(folder), "--out", str(tmp_path / "c.bag"), "--no-boxes",
                       "--quiet"]) == 0


# --- Conventions --------------------------------------------------------------------------------

def test_label_box_label_round_trip_is_within_1e_6_and_rewrites_the_same_line(kitti_fixture):
    compared = 0
    for stem, calib, labels in frames(kitti_fixture):
        lines = (kitti_fixture / "label_2" / f"{stem}.txt").read_text().splitlines()
        for line, label in labels:
            if label.type == kitti.DONT_CARE:
                continue
            box = kitti.label_to_box(label, calib)
            back = kitti.box_to_label(box, calib, label.type, label.truncated, label.occluded,
                                      label.alpha, label.bbox)
            np.testing.assert_allclose(back.dimensions, label.dimensions, rtol=0, atol=1e-6)
            np.testing.assert_allclose(back.location, label.location, rtol=0, atol=1e-6)
            assert back.rotation_y == pytest.approx(label.rotation_y, abs=1e-6)
            assert kitti.format_label(back) == lines[line]
            compared += 1
    assert compared == len(ORACLE)


def test_round_trips_hold_for_every_heading_and_box_to_label_to_box(kitti_fixture):
    calib = kitti.read_calib(kitti_fixture / "calib" / "000000.txt")
    rng = np.random.default_rng(5)
    for rotation_y in np.r_[np.linspace(-math.pi, math.pi, 37)[:-1], rng.uniform(-3.14, 3.14, 40)]:
        label = kitti.Label("Car", 0.0, 0, 0.0, (0.0, 0.0, 1.0, 1.0),
                            tuple(rng.uniform(0.5, 5.0, 3)),
                            (rng.uniform(-40, 40), rng.uniform(1.0, 2.5), rng.uniform(2, 80)),
                            float(rotation_y))
        box = kitti.label_to_box(label, calib)
        back = kitti.box_to_label(box, calib, "Car")
        np.testing.assert_allclose(back.location, label.location, rtol=0, atol=1e-6)
        np.testing.assert_allclose(back.dimensions, label.dimensions, rtol=0, atol=1e-6)
        assert abs(kitti._wrap(back.rotation_y - label.rotation_y)) < 1e-6
        again = kitti.label_to_box(back, calib)
        np.testing.assert_allclose(again.centre, box.centre, rtol=0, atol=1e-9)
        np.testing.assert_allclose(again.rotation, box.rotation, rtol=0, atol=1e-9)
        from_pose = kitti.Box.from_pose(box.centre, box.quaternion, box.size)
        np.testing.assert_allclose(from_pose.rotation, box.rotation, rtol=0, atol=1e-12)


def test_box_axes_are_a_right_handed_rotation_with_up_along_the_cameras_minus_y(kitti_fixture):
    calib = kitti.read_calib(kitti_fixture / "calib" / "000008.txt")
    _, label = kitti.read_labels(kitti_fixture / "label_2" / "000008.txt")[0]
    box = kitti.label_to_box(label, calib)
    np.testing.assert_allclose(box.rotation.T @ box.rotation, np.eye(3), atol=1e-12)
    assert np.linalg.det(box.rotation) == pytest.approx(1.0, abs=1e-12)
    rotation, _ = calib.rigid_velo_to_rect()
    np.testing.assert_allclose(rotation @ box.rotation[:, 2], [0, -1, 0], atol=1e-12)
    assert box.size == (label.dimensions[2], label.dimensions[1], label.dimensions[0])
    np.testing.assert_allclose(calib.to_rect(box.centre),
                               np.add(label.location, [0, -label.dimensions[0] / 2, 0]),
                               atol=1e-12)


def test_closest_rotation_is_orthonormal_and_within_1e_7_of_kittis_matrix(kitti_fixture):
    for _, calib, _ in frames(kitti_fixture):
        linear, _ = calib.velo_to_rect()
        rotation, _ = calib.rigid_velo_to_rect()
        np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-14)
        assert np.abs(linear - rotation).max() < 1e-7


def test_quaternions_round_trip_through_half_turns_and_small_angles():
    rng = np.random.default_rng(2)
    rotations = [np.diag([1.0, -1.0, -1.0]), np.diag([-1.0, 1.0, -1.0]),
                 np.diag([-1.0, -1.0, 1.0]), np.eye(3)]
    rotations += [kitti.closest_rotation(rng.normal(size=(3, 3))) for _ in range(50)]
    for rotation in rotations:
        if np.linalg.det(rotation) < 0:
            continue
        quaternion = quaternion_from_matrix(rotation)
        assert quaternion[3] >= 0.0
        np.testing.assert_allclose(rotation_matrix(quaternion), rotation,
                                   atol=1e-12)


def test_alpha_and_the_2d_box_agree_with_kittis_labels(kitti_fixture):
    """KITTI's alphas and hand-drawn 2-D boxes are not computed exactly as ours: alpha within
    0.04 rad (0.033 measured, for a car 3.7 m away), the projected box within IoU 0.8 where the
    object is not truncated (KITTI clips truncated ones to the image)."""
    for _, calib, labels in frames(kitti_fixture):
        for _, label in labels:
            if label.type == kitti.DONT_CARE:
                continue
            back = kitti.box_to_label(kitti.label_to_box(label, calib), calib, label.type)
            assert abs(kitti._wrap(back.alpha - label.alpha)) < 0.04
            if label.truncated == 0.0:
                assert iou(back.bbox, label.bbox) > 0.8, (label, back.bbox)


def iou(a, b):
    width = min(a[2], b[2]) - max(a[0], b[0])
    height = min(a[3], b[3]) - max(a[1], b[1])
    inter = max(width, 0.0) * max(height, 0.0)
    area = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1])
    return inter / (area - inter)


def test_road_plane_in_the_lidar_frame_is_under_the_sensor_and_holds_the_cameras_plane(
        kitti_fixture):
    for stem, calib, _ in frames(kitti_fixture):
        plane = kitti.read_plane(kitti_fixture / "planes" / f"{stem}.txt")
        normal, offset = kitti.plane_to_velo(plane, calib)
        assert np.linalg.norm(normal) == pytest.approx(1.0) and normal[2] > 0.99
        assert 1.5 < offset < 1.9  # the HDL-64E is mounted 1.73 m above the road
        a, b, c, d = plane
        on_plane_rect = np.array([[0.0, -d / b, 0.0], [3.0, -(d + 3 * a + 20 * c) / b, 20.0]])
        np.testing.assert_allclose(calib.to_velo(on_plane_rect) @ normal + offset, 0.0,
                                   atol=1e-9)


def test_parse_frames_takes_numbers_ranges_and_lists():
    assert kitti.parse_frames("000000-000004") == [0, 1, 2, 3, 4]
    assert kitti.parse_frames("8,0-1, 3") == [0, 1, 3, 8]
    for bad in ("", "a", "4-2", "1-", "-3", "1;2"):
        with pytest.raises(Exception):
            kitti.parse_frames(bad)


# --- Bad input ----------------------------------------------------------------------------------

def run_failing(argv, capsys):
    status = kitti.main([*argv, "--quiet"])
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return status, err


def test_a_missing_folder_is_exit_2_naming_it(tmp_path, capsys):
    status, err = run_failing([str(tmp_path / "nowhere"), "--out", str(tmp_path / "x.bag")],
                              capsys)
    assert status == 2 and "nowhere: no such folder" in err
    assert list(tmp_path.iterdir()) == []


def test_a_frame_without_calib_is_exit_2_naming_the_file_and_leaves_no_bag(
        kitti_fixture, tmp_path, capsys):
    folder = small_kitti(kitti_fixture, tmp_path / "kitti")
    (folder / "calib" / "000001.txt").unlink()
    status, err = run_failing([str(folder), "--out", str(tmp_path / "x.bag")], capsys)
    assert status == 2 and "calib/000001.txt: no such file" in err
    assert_nothing_written(tmp_path)


def test_a_malformed_label_line_is_exit_2_naming_file_and_line_and_leaves_no_bag(
        kitti_fixture, tmp_path, capsys):
    folder = small_kitti(kitti_fixture, tmp_path / "kitti")
    labels = folder / "label_2" / "000001.txt"
    lines = labels.read_text().splitlines()
    lines[1] = lines[1].rsplit(" ", 1)[0]  # rotation_y missing
    labels.write_text("\n".join(lines) + "\n")
    status, err = run_failing([str(folder), "--out", str(tmp_path / "x.bag")], capsys)
    assert status == 2 and "label_2/000001.txt line 2: expected 15 fields" in err
    assert_nothing_written(tmp_path)

    lines[1] = lines[1] + " zero"
    labels.write_text("\n".join(lines) + "\n")
    status, err = run_failing([str(folder), "--out", str(tmp_path / "x.bag")], capsys)
    assert status == 2 and "label_2/000001.txt line 2: could not convert" in err
    assert_nothing_written(tmp_path)


def test_a_truncated_cloud_stops_the_run_midway_and_leaves_no_bag(kitti_fixture, tmp_path,
                                                                  capsys):
    folder = small_kitti(kitti_fixture, tmp_path / "kitti")
    cloud = folder / "velodyne" / "000001.bin"
    data = cloud.read_bytes()
    cloud.unlink()
    cloud.write_bytes(data[:-6])
    status, err = run_failing([str(folder), "--out", str(tmp_path / "x.bag")], capsys)
    assert status == 2 and "velodyne/000001.bin" in err and "whole number of points" in err
    assert_nothing_written(tmp_path)


def test_frames_that_are_not_there_are_exit_2(kitti_fixture, tmp_path, capsys):
    status, err = run_failing([str(kitti_fixture), "--out", str(tmp_path / "x.bag"),
                               "--frames", "8-12"], capsys)
    assert status == 2 and "no frame 000010, 000011, 000012 (3 of the 5 asked for)" in err
    assert list(tmp_path.iterdir()) == []


def test_an_output_folder_that_does_not_exist_is_exit_1(kitti_fixture, tmp_path, capsys):
    status, err = run_failing([str(kitti_fixture), "--out", str(tmp_path / "no" / "x.bag"),
                               "--frames", "0"], capsys)
    assert status == 1 and "does not exist" in err


def test_the_bag_never_replaces_a_file_it_reads(kitti_fixture, tmp_path, capsys):
    folder = small_kitti(kitti_fixture, tmp_path / "kitti")
    cloud = folder / "velodyne" / "000001.bin"
    before = cloud.read_bytes()
    status, err = run_failing([str(folder), "--out", str(cloud)], capsys)
    assert status == 2 and "would replace the input" in err and "000001.bin" in err
    assert cloud.read_bytes() == before


def test_a_huge_frame_range_is_refused_before_it_is_listed(kitti_fixture, tmp_path):
    # Listed first, 0-99999999999 took 23 GB before the out-of-memory killer stopped it.
    for frames, message in (("0-99999999999", "frame numbers go up to"),
                            ("0-200000", "at most 100000 at once")):
        with pytest.raises(argparse.ArgumentTypeError, match=message):
            kitti.parse_frames(frames)
    assert kitti.parse_frames("0-2,1-3,9") == [0, 1, 2, 3, 9]


def test_stamps_past_ros_times_range_are_refused_before_writing(kitti_fixture, tmp_path, capsys):
    status, err = run_failing([str(kitti_fixture), "--out", str(tmp_path / "x.bag"),
                               "--start-time", "4294967295.5"], capsys)
    assert status == 2 and "past ROS time's 2^32 s" in err
    assert list(tmp_path.iterdir()) == []


def test_bad_options_are_exit_2(kitti_fixture, tmp_path, capsys):
    for extra in (["--frames", "a-b"], ["--start-time", "-1"], ["--frame-id", ""],
                  ["--out", ""]):
        with pytest.raises(SystemExit) as exited:
            kitti.main([str(kitti_fixture), "--out", str(tmp_path / "x.bag"), *extra])
        assert exited.value.code == 2
    # "²" is a digit to str.isdigit, but no frame number.
    with pytest.raises(SystemExit) as exited:
        kitti.main([str(kitti_fixture), "--out", str(tmp_path / "x.bag"), "--frames", "0-\u00b2"])
    assert exited.value.code == 2
    assert "expected frame numbers and ranges" in capsys.readouterr().err


def test_the_script_tells_the_truth_in_help_and_fails_in_one_line(kitti_fixture, tmp_path):
    shown = subprocess.run([sys.executable, str(SCRIPT), "--help"], capture_output=True,
                           text=True, check=True)
    for option in ("--frames", "--start-time", "--frame-id", "--no-boxes", "--out"):
        assert option in shown.stdout
    folder = small_kitti(kitti_fixture, tmp_path / "kitti")
    (folder / "calib" / "000000.txt").unlink()
    failed = subprocess.run([sys.executable, str(SCRIPT), str(folder), "--out",
                             str(tmp_path / "x.bag")], capture_output=True, text=True)
    assert failed.returncode == 2
    assert failed.stderr.startswith("kitti_to_bag: error: ") and failed.stderr.count("\n") == 1
