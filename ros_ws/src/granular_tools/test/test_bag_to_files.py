"""bag to files, offline mode: pairing policy, file formats, and bad input."""
import copy
import json

import numpy as np
import pytest

import bagmaker
from bagmaker import CLOUD_TOPIC, DETECTIONS_TOPIC
from granular_tools.bag_to_files import offline
from granular_tools.frames_folder import stamp_name
from granular_tools.simulation import cli as simulate


def run(bag, out, *extra):
    return offline.main(["--bag", str(bag), "--out", str(out), "--quiet", *extra])


def stems(folder, sub, suffix):
    return sorted(p.name[:-len(suffix)] for p in (folder / sub).iterdir())


def read_pcd(path):
    raw = path.read_bytes()
    header_end = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
    header = dict(line.split(" ", 1) for line in raw[:header_end].decode().splitlines()
                  if not line.startswith("#"))
    dtype = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("intensity", "u1"),
                      ("timestamp", "<f8")])
    return header, np.frombuffer(raw[header_end:], dtype=dtype)


def test_pairs_only_stamps_within_slop_and_skips_frames_without_detections(tmp_path):
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.cloud(0.0)), (DETECTIONS_TOPIC, bagmaker.detections(0.004)),
        (CLOUD_TOPIC, bagmaker.cloud(0.1)), (DETECTIONS_TOPIC, bagmaker.detections(0.115)),
        (CLOUD_TOPIC, bagmaker.cloud(0.2)), (DETECTIONS_TOPIC, bagmaker.detections(0.2095, ())),
        (DETECTIONS_TOPIC, bagmaker.detections(0.295)), (CLOUD_TOPIC, bagmaker.cloud(0.3)),
    ])
    assert run(bag, tmp_path / "out") == 0
    expected = [stamp_name(bagmaker.stamp(t)) for t in (0.0, 0.3)]
    assert stems(tmp_path / "out", "pcd", ".pcd") == expected
    assert stems(tmp_path / "out", "detections_3d", ".json") == expected


def test_pcd_keeps_every_field_and_value_of_the_cloud(tmp_path):
    points = np.array([[1.5, -2.25, -2.3], [10.0, 0.5, 1.25], [-3.0, 4.0, 0.0]])
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.cloud(0.0, points)), (DETECTIONS_TOPIC, bagmaker.detections(0.0))])
    assert run(bag, tmp_path / "out") == 0
    header, data = read_pcd(next((tmp_path / "out" / "pcd").iterdir()))
    assert header["FIELDS"] == "x y z intensity timestamp"
    assert header["SIZE"] == "4 4 4 1 8" and header["TYPE"] == "F F F U F"
    assert header["WIDTH"] == "3" and header["HEIGHT"] == "1" and header["POINTS"] == "3"
    np.testing.assert_array_equal(np.stack([data["x"], data["y"], data["z"]], 1),
                                  points.astype(np.float32))
    np.testing.assert_array_equal(data["intensity"], [0, 1, 2])
    assert data["timestamp"][0] == pytest.approx(bagmaker.START)


def test_json_has_the_reports_layout(tmp_path):
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.cloud(0.0)),
        (DETECTIONS_TOPIC, bagmaker.detections(0.001, ("Sedan", "Jeep")))])
    assert run(bag, tmp_path / "out") == 0
    document = json.loads(next((tmp_path / "out" / "detections_3d").iterdir()).read_text())
    stamp = bagmaker.stamp(0.001)
    assert document["header"]["stamp"] == {"secs": stamp.secs, "nsecs": stamp.nsecs}
    assert document["header"]["frame_id"] == "velodyne"
    jeep = document["detections"][1]
    assert (jeep["id"], jeep["label"], jeep["score"]) == (101, "Jeep", 1.0)
    assert jeep["bbox"]["position"]["position"] == {"x": 6.0, "y": -1.0, "z": -1.5}
    assert jeep["bbox"]["position"]["orientation"] == {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
    assert jeep["bbox"]["size"] == {"x": 4.5, "y": 1.8, "z": 1.4}
    assert jeep["velocity"]["linear"]["x"] == 3.0 and "angular" in jeep["velocity"]


def test_simulated_drive_converts_deterministically(tmp_path):
    bag = tmp_path / "drive.bag"
    assert simulate.main(["--out", str(bag), "--duration", "2", "--seed", "8", "--quiet"]) == 0
    assert run(bag, tmp_path / "a") == 0 and run(bag, tmp_path / "b") == 0
    names = stems(tmp_path / "a", "pcd", ".pcd")
    assert 5 <= len(names) <= 15, "about half of the 20 clouds pair within 10 ms"
    for sub, suffix in (("pcd", ".pcd"), ("detections_3d", ".json")):
        for name in names:
            assert (tmp_path / "a" / sub / (name + suffix)).read_bytes() == \
                (tmp_path / "b" / sub / (name + suffix)).read_bytes()


def test_bag_without_a_topic_names_the_topics_it_has(tmp_path, capsys):
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, bagmaker.cloud(0.0))])
    assert run(bag, tmp_path / "out") == 1
    error = capsys.readouterr().err
    assert f"no topic {DETECTIONS_TOPIC}" in error and CLOUD_TOPIC in error
    assert "--clouds-only" in error
    assert not (tmp_path / "out").exists()


def test_a_clouds_only_bag_gives_every_cloud_in_its_own_layout_and_no_boxes(tmp_path, capsys):
    points = np.array([[4.0, 1.0, -1.7], [12.5, -3.0, 0.25], [-6.0, 2.0, -1.0]])
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.velodyne_cloud(0.0, points)),
        (CLOUD_TOPIC, bagmaker.velodyne_cloud(0.1, points[:2])),
        (CLOUD_TOPIC, bagmaker.velodyne_cloud(0.2, points[:1]))])
    assert offline.main(["--bag", str(bag), "--out", str(tmp_path / "out"), "--clouds-only"]) == 0
    assert "clouds read 3, written 3 (clouds only)" in capsys.readouterr().out
    assert stems(tmp_path / "out", "pcd", ".pcd") == [
        stamp_name(bagmaker.stamp(t)) for t in (0.0, 0.1, 0.2)]
    assert list((tmp_path / "out" / "detections_3d").iterdir()) == []
    first = (tmp_path / "out" / "pcd" / (stamp_name(bagmaker.stamp(0.0)) + ".pcd")).read_bytes()
    header, _, data = first.partition(b"DATA binary\n")
    assert b"FIELDS x y z intensity ring time\n" in header
    record = np.frombuffer(data, dtype=np.dtype({
        "names": ["x", "y", "z", "ring"], "formats": ["<f4", "<f4", "<f4", "<u2"],
        "offsets": [0, 4, 8, 16], "itemsize": 22}))
    np.testing.assert_array_equal(np.stack([record["x"], record["y"], record["z"]], 1),
                                  points.astype(np.float32))
    np.testing.assert_array_equal(record["ring"], [0, 1, 2])


def test_cloud_without_xyz_is_an_error_and_nothing_is_written(tmp_path, capsys):
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.cloud_without_xyz(0.0)),
        (DETECTIONS_TOPIC, bagmaker.detections(0.0))])
    assert run(bag, tmp_path / "out") == 1
    assert "no x/y/z field" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == [bag]


def test_existing_results_are_kept_unless_overwrite(tmp_path, capsys):
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.cloud(0.0)), (DETECTIONS_TOPIC, bagmaker.detections(0.0))])
    out = tmp_path / "out"
    assert run(bag, out) == 0
    (out / "pcd" / "older.pcd").write_text("older results")
    assert run(bag, out) == 1
    assert "holds results of bag_to_files; pass --overwrite" in capsys.readouterr().err
    assert (out / "pcd" / "older.pcd").exists()
    assert run(bag, out, "--overwrite") == 0
    assert not (out / "pcd" / "older.pcd").exists() and len(stems(out, "pcd", ".pcd")) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.bag", "out"]


def test_a_folder_of_other_files_is_never_replaced(tmp_path, capsys):
    bag = bagmaker.write(tmp_path / "in.bag", [
        (CLOUD_TOPIC, bagmaker.cloud(0.0)), (DETECTIONS_TOPIC, bagmaker.detections(0.0))])
    out = tmp_path / "out"
    out.mkdir()
    (out / "thesis.tex").write_text("years of work")
    assert run(bag, out, "--overwrite") == 1
    assert f"{out}: output folder holds files that no granular tool wrote" in \
        capsys.readouterr().err
    assert [p.name for p in out.iterdir()] == ["thesis.tex"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.bag", "out"]


def test_unreadable_bag_and_bad_slop_are_errors(tmp_path, capsys):
    not_a_bag = tmp_path / "in.bag"
    not_a_bag.write_text("hello")
    assert run(not_a_bag, tmp_path / "out") == 1
    assert str(not_a_bag) in capsys.readouterr().err
    # A bad value is a bad option (2), as an unknown one is, in a file as on the line.
    assert run(not_a_bag, tmp_path / "out", "--slop", "-1") == 2
    assert "slop: -1.0 is out of range (allowed: > 0.0 and finite)" in capsys.readouterr().err
    assert run(not_a_bag, tmp_path / "out", "--slop", "inf") == 2
    assert "slop: inf is out of range" in capsys.readouterr().err
    assert run(not_a_bag, tmp_path / "out", "--queue-size", "0") == 2
    assert "queue_size: 0 is out of range (allowed: >= 1)" in capsys.readouterr().err
    config = tmp_path / "bag_to_files.yaml"
    for value in ("0", ".inf"):
        config.write_text(f"slop: {value}\n")
        assert run(not_a_bag, tmp_path / "out", "--config", str(config)) == 2
        assert f"{config}.slop: " in capsys.readouterr().err


def test_pcd_and_json_read_back_into_the_messages_they_came_from(tmp_path):
    from granular_tools.messages import dict_to_detections, pcd_to_cloud

    cloud = bagmaker.cloud(0.0, np.array([[1.0, 2.0, 3.0], [-4.5, 0.25, -2.3]]))
    detections = bagmaker.detections(0.002, ("Sedan", "SchoolBus"))
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, cloud),
                                               (DETECTIONS_TOPIC, detections)])
    assert run(bag, tmp_path / "out") == 0
    name = stamp_name(cloud.header.stamp)
    back = pcd_to_cloud(str(tmp_path / "out" / "pcd" / f"{name}.pcd"), "velodyne",
                        cloud.header.stamp)
    read = read_pcd(tmp_path / "out" / "pcd" / f"{name}.pcd")[1]
    assert back.data == read.tobytes() and back.width == 2
    assert [f.name for f in back.fields] == ["x", "y", "z", "intensity", "timestamp"]
    document = json.loads((tmp_path / "out" / "detections_3d" / f"{name}.json").read_text())
    assert dict_to_detections(document) == detections


def test_boxes_with_nan_or_infinite_numbers_are_skipped_and_counted(tmp_path, capsys):
    broken = bagmaker.detections(0.0, ("Sedan", "SUV", "Jeep"))
    broken.detections[0].bbox.position.position.x = float("nan")
    broken.detections[1].bbox.size.y = float("inf")
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, bagmaker.cloud(0.0)),
                                               (DETECTIONS_TOPIC, broken)])
    assert offline.main(["--bag", str(bag), "--out", str(tmp_path / "out")]) == 0
    assert "detections skipped: 2 a box with NaN or infinite numbers" in capsys.readouterr().out
    (document,) = [json.loads(p.read_text()) for p in (tmp_path / "out" / "detections_3d").iterdir()]
    assert [d["label"] for d in document["detections"]] == ["Jeep"]


def _static_transform(parent, child, translation, quaternion):
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage

    transform = TransformStamped()
    transform.header.stamp = bagmaker.stamp(0.0)
    transform.header.frame_id, transform.child_frame_id = parent, child
    transform.transform.translation.x, transform.transform.translation.y, \
        transform.transform.translation.z = translation
    r = transform.transform.rotation
    r.x, r.y, r.z, r.w = quaternion
    return TFMessage([transform])


def test_detections_in_another_frame_are_moved_into_the_clouds_with_the_bags_tf(tmp_path):
    elsewhere = bagmaker.detections(0.0, ("Sedan",))
    elsewhere.header.frame_id = "base_link"
    elsewhere.detections[0].header.frame_id = "base_link"
    # base_link -> velodyne: the sensor 1.5 m ahead and turned 90 degrees left.
    half = np.sqrt(0.5)
    tf_static = _static_transform("velodyne", "base_link", (0.0, 1.5, 0.0), (0.0, 0.0, half, half))
    bag = bagmaker.write(tmp_path / "in.bag", [("/tf_static", tf_static),
                                               (CLOUD_TOPIC, bagmaker.cloud(0.0)),
                                               (DETECTIONS_TOPIC, elsewhere)],
                         stamp=bagmaker.stamp(0.0))
    with_tf = tmp_path / "out"
    assert run(bag, with_tf) == 0
    (document,) = [json.loads(p.read_text()) for p in (with_tf / "detections_3d").iterdir()]
    (box,) = document["detections"]
    assert box["header"]["frame_id"] == "velodyne"
    # (5, -1, -1.5) in base_link, turned 90 deg about z: (1, 5, -1.5), then 1.5 m along y.
    position = box["bbox"]["position"]["position"]
    assert position == pytest.approx({"x": 1.0, "y": 6.5, "z": -1.5}, abs=1e-9)
    orientation = box["bbox"]["position"]["orientation"]
    assert orientation == pytest.approx({"x": 0.0, "y": 0.0, "z": half, "w": half}, abs=1e-9)


def test_detections_in_another_frame_without_a_transform_are_skipped_and_counted(tmp_path,
                                                                                  capsys):
    elsewhere = bagmaker.detections(0.0, ("Sedan", "SUV"))
    elsewhere.detections[0].header = copy.deepcopy(elsewhere.detections[0].header)
    elsewhere.detections[0].header.frame_id = "map"
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, bagmaker.cloud(0.0)),
                                               (DETECTIONS_TOPIC, elsewhere)])
    assert offline.main(["--bag", str(bag), "--out", str(tmp_path / "out")]) == 0
    assert "1 in frame 'map' with no transform to the cloud's 'velodyne'" in \
        capsys.readouterr().out
    (document,) = [json.loads(p.read_text()) for p in (tmp_path / "out" / "detections_3d").iterdir()]
    assert [d["label"] for d in document["detections"]] == ["SUV"]
