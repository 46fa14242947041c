"""kitti_labels: KITTI's label_2 into a frames folder and back gives the same boxes (within
1 mm and 0.001 rad); the LiDAR-frame convention; bad input named."""
import json
import math
import pathlib
import shutil

import numpy as np
import pytest

import hostile
from granular_tools import kitti
from granular_tools.labelling import kitti_labels



@pytest.fixture
def frames(kitti_frames, tmp_path):
    copy = tmp_path / "frames"
    shutil.copytree(kitti_frames, copy)
    return copy


def boxes_of(folder):
    """{file stem: [(type, dimensions, location, rotation_y)]} of a label folder, DontCare
    left out."""
    result = {}
    for path in sorted(pathlib.Path(folder).glob("*.txt")):
        result[path.stem] = [(label.type, label.dimensions, label.location, label.rotation_y)
                             for _, label in kitti.read_labels(str(path))
                             if label.type != kitti.DONT_CARE]
    return result


def assert_same_boxes(got, expected):
    assert sorted(got) == sorted(expected)
    for stem, labels in expected.items():
        assert len(got[stem]) == len(labels), stem
        for (kind, dims, location, ry), (kind2, dims2, location2, ry2) in zip(got[stem], labels):
            assert kind == kind2
            np.testing.assert_allclose(dims, dims2, atol=1e-3, err_msg=stem)
            np.testing.assert_allclose(location, location2, atol=1e-3, err_msg=stem)
            turn = (ry - ry2 + math.pi) % (2 * math.pi) - math.pi
            assert abs(turn) < 1e-3, (stem, ry, ry2)


def test_label_2_imported_and_exported_again_gives_the_same_boxes(frames, tmp_path, kitti_fixture):
    calib = ["--calib", str(kitti_fixture)]
    assert kitti_labels.main(["import", str(kitti_fixture / "label_2"), "--into", str(frames),
                              "--quiet"] + calib) == 0
    assert kitti_labels.main(["export", str(frames), "--out", str(tmp_path / "label_2"),
                              "--quiet"] + calib) == 0
    expected = boxes_of(kitti_fixture / "label_2")
    assert sum(map(len, expected.values())) == 27
    assert_same_boxes(boxes_of(tmp_path / "label_2"), expected)
    # ids as kitti_to_bag gives them: frame * 1000 + line
    document = json.loads(next((frames / "detections_3d").glob("*800000000.json")).read_text())
    assert [d["id"] for d in document["detections"]] == list(range(8000, 8006))


def test_a_frames_folder_from_kitti_exports_its_label_lines(frames, tmp_path, kitti_fixture):
    assert kitti_labels.main(["export", str(frames), "--out", str(tmp_path / "label_2"),
                              "--calib", str(kitti_fixture / "calib"), "--quiet"]) == 0
    assert_same_boxes(boxes_of(tmp_path / "label_2"), boxes_of(kitti_fixture / "label_2"))


def test_without_calib_the_lidar_convention_round_trips(frames, tmp_path):
    exported, again = tmp_path / "lidar", tmp_path / "again"
    assert kitti_labels.main(["export", str(frames), "--out", str(exported), "--decimals", "6",
                              "--quiet"]) == 0
    assert sorted(p.stem for p in exported.glob("*.txt")) == \
        sorted(p.stem for p in (frames / "pcd").glob("*.pcd"))
    assert kitti_labels.main(["import", str(exported), "--into", str(frames), "--quiet"]) == 0
    assert kitti_labels.main(["export", str(frames), "--out", str(again), "--decimals", "6",
                              "--quiet"]) == 0
    assert boxes_of(again) == boxes_of(exported)


def test_the_lidar_convention_is_kittis_camera_axes_at_the_sensor():
    box = kitti.Box.from_pose((10.0, 2.0, -1.0), (0.0, 0.0, math.sin(0.15), math.cos(0.15)),
                              (4.0, 1.8, 1.6))  # yaw 0.3 rad
    label = kitti.box_to_label(box, kitti_labels.LIDAR_AS_CAMERA, "Car",
                               bbox=kitti_labels.NO_IMAGE_BOX)
    np.testing.assert_allclose(label.location, (-2.0, 1.0 + 0.8, 10.0), atol=1e-12)
    assert label.rotation_y == pytest.approx(-0.3 - math.pi / 2)
    assert label.dimensions == pytest.approx((1.6, 1.8, 4.0))


def test_free_text_labels_survive_the_label_files(frames, tmp_path):
    path = next((frames / "detections_3d").glob("*.json"))
    document = json.loads(path.read_text())
    document["detections"][0]["label"] = "Medium-sized Truck"
    path.write_text(json.dumps(document))
    assert kitti_labels.main(["export", str(frames), "--out", str(tmp_path / "out"),
                              "--quiet"]) == 0
    line = (tmp_path / "out" / (path.stem + ".txt")).read_text().splitlines()[0]
    assert line.startswith("Medium%2Dsized%20Truck ")
    assert kitti_labels.main(["import", str(tmp_path / "out"), "--into", str(frames),
                              "--quiet"]) == 0
    assert json.loads(path.read_text())["detections"][0]["label"] == "Medium-sized Truck"


def test_stamps_that_are_not_the_kitti_frames_are_refused(frames, tmp_path, kitti_fixture):
    result = hostile.run(hostile.tool("granular_tools", "kitti_labels") + [
        "export", frames, "--out", tmp_path / "out", "--calib", kitti_fixture, "--start-time", "5"])
    hostile.assert_fails_clearly(result, 2, "--start-time")
    assert not (tmp_path / "out").exists()


def test_a_malformed_label_line_is_named_and_nothing_is_written(frames, tmp_path, kitti_fixture):
    labels = tmp_path / "label_2"
    shutil.copytree(kitti_fixture / "label_2", labels)
    (labels / "000003.txt").write_text("Car 0.00 0 1.2 1 2 3 4 1.5 1.6 four 1 2 3 0.1\n")
    before = hostile.snapshot(frames)
    result = hostile.run(hostile.tool("granular_tools", "kitti_labels") + [
        "import", labels, "--into", frames, "--calib", kitti_fixture])
    hostile.assert_fails_clearly(result, 2, labels / "000003.txt", "line 1")
    assert hostile.snapshot(frames) == before


def test_an_unreadable_detections_file_stops_the_import_before_any_write(frames, kitti_fixture):
    broken = next((frames / "detections_3d").glob("*.json"))
    broken.write_text("{not json")
    before = hostile.snapshot(frames / "detections_3d")
    result = hostile.run(hostile.tool("granular_tools", "kitti_labels") + [
        "import", kitti_fixture / "label_2", "--into", frames, "--calib", kitti_fixture])
    hostile.assert_fails_clearly(result, 1, broken)
    assert hostile.snapshot(frames / "detections_3d") == before


def test_export_never_replaces_the_folder_it_reads(frames, tmp_path):
    # Even with --overwrite: the frames folder itself, or a granular folder holding it.
    run = tmp_path / "run"
    shutil.copytree(frames, run / "frames")
    (run / ".granular.json").write_text('{"tool": "run_cuboids"}')
    for folder, out in ((frames, frames), (run / "frames", run)):
        before = hostile.snapshot(folder)
        result = hostile.run(hostile.tool("granular_tools", "kitti_labels") + [
            "export", folder, "--out", out, "--overwrite"])
        hostile.assert_fails_clearly(result, 1, "would replace the input")
        assert hostile.snapshot(folder) == before


def test_export_does_not_replace_a_users_folder(frames, tmp_path):
    mine = hostile.user_folder(tmp_path / "mine")
    result = hostile.run(hostile.tool("granular_tools", "kitti_labels") + [
        "export", frames, "--out", mine, "--overwrite"])
    hostile.assert_fails_clearly(result, 1, mine)
    assert (mine / "notes.txt").read_text() == "my notes\n"
