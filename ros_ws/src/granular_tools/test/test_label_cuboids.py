"""label_cuboids on a frames folder, without rviz: saving and backups, the frames it skips,
the cuboids it starts from, and the folders it refuses."""
import argparse
import json
import os
import subprocess

import pytest

import bagmaker
import hostile
from bagmaker import CLOUD_TOPIC
from granular_tools.geometry import Cuboid
from granular_tools.labelling.node import _prepare_frames, frame_index
from granular_tools.labelling.session import Session, SessionError
from granular_tools.output import OutputError
from test_labelling import document_text


def frames_folder(tmp_path, count=3, with_json=True):
    folder = tmp_path / "frames"
    (folder / "pcd").mkdir(parents=True)
    stamps = [f"158610274{k}100000000" for k in range(count)]
    for k, stamp in enumerate(stamps):
        (folder / "pcd" / (stamp + ".pcd")).write_text(
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n")
        if with_json:
            (folder / "detections_3d").mkdir(exist_ok=True)
            (folder / "detections_3d" / (stamp + ".json")).write_text(
                document_text((k, "Car", "10.0")))
    return folder, stamps


def test_saving_backs_up_the_file_as_it_was_once(tmp_path):
    folder, stamps = frames_folder(tmp_path)
    original = (folder / "detections_3d" / (stamps[0] + ".json")).read_text()
    session = Session(folder)
    with session.opened():
        labels = session.load(stamps[0])
        assert session.save(stamps[0]) is None  # nothing changed: nothing written
        labels.set_label(labels.entries[0].key, "Van")
        assert session.save(stamps[0]) == str(folder / "detections_3d" / (stamps[0] + ".json"))
        labels.set_label(labels.entries[0].key, "Truck")
        session.save(stamps[0])
    backup = folder / "labelling_backup" / (stamps[0] + ".json")
    assert backup.read_text() == original
    saved = json.loads((folder / "detections_3d" / (stamps[0] + ".json")).read_text())
    assert saved["detections"][0]["label"] == "Truck"
    # A later session keeps the first backup.
    session = Session(folder)
    with session.opened():
        labels = session.load(stamps[0])
        labels.set_label(labels.entries[0].key, "Car")
        session.save(stamps[0])
    assert backup.read_text() == original


def test_undo_back_to_the_saved_state_is_unchanged_and_past_it_is_saved(tmp_path):
    folder, stamps = frames_folder(tmp_path, 1)
    session = Session(folder)
    with session.opened():
        labels = session.load(stamps[0])
        labels.set_label(labels.entries[0].key, "Van")
        session.save(stamps[0])
        labels.set_label(labels.entries[0].key, "Truck")
        labels.undo()
        assert not session.unsaved(stamps[0])
        labels.undo()
        assert session.unsaved(stamps[0])
        session.save(stamps[0])
    assert (folder / "detections_3d" / (stamps[0] + ".json")).read_text() == \
        (folder / "labelling_backup" / (stamps[0] + ".json")).read_text()


def test_a_folder_without_detections_starts_with_none_and_gets_its_files(tmp_path):
    folder, stamps = frames_folder(tmp_path, 2, with_json=False)
    session = Session(folder)
    with session.opened():
        assert session.names == stamps
        labels = session.load(stamps[1])
        assert labels.entries == ()
        labels.add("Car", Cuboid((5.0, 1.0, -1.0), (4.5, 1.8, 1.5)))
        session.save(stamps[1])
    assert len(json.loads((folder / "detections_3d" / (stamps[1] + ".json")).read_text())[
        "detections"]) == 1
    assert (folder / "labelling_backup" / (stamps[1] + ".json.absent")).exists()
    assert not (folder / "detections_3d" / (stamps[0] + ".json")).exists()


def test_a_detections_file_that_does_not_parse_is_named_and_its_frame_skipped(tmp_path):
    folder, stamps = frames_folder(tmp_path)
    broken = folder / "detections_3d" / (stamps[1] + ".json")
    broken.write_text('{"header": {}, "detections": [{"id": 1,')
    session = Session(folder)
    with session.opened():
        assert session.names == [stamps[0], stamps[2]]
        assert str(broken) in session.skipped[stamps[1]]
        assert "not valid JSON" in session.skipped[stamps[1]]
    assert broken.read_text() == '{"header": {}, "detections": [{"id": 1,'


def test_a_detection_without_a_field_is_named_with_its_key(tmp_path):
    folder, stamps = frames_folder(tmp_path, 1)
    path = folder / "detections_3d" / (stamps[0] + ".json")
    path.write_text(path.read_text().replace('"size": {"x": 4.5, ', '"size": {'))
    with pytest.raises(SessionError, match=r"detections\[0\]\.bbox\.size\.x: missing"):
        with Session(folder).opened():
            pass


def test_cuboids_give_the_first_boxes_until_the_frame_is_saved(tmp_path):
    folder, stamps = frames_folder(tmp_path, 2)
    cuboids = tmp_path / "cuboids"
    cuboids.mkdir()
    for stamp in stamps:
        (cuboids / (stamp + ".json")).write_text(document_text((7, "Van", "30.0")))
    session = Session(folder, cuboids)
    with session.opened():
        labels = session.load(stamps[0])
        assert [e.detection["label"] for e in labels.entries] == ["Van"]
        labels.set_label(labels.entries[0].key, "Truck")
        session.save(stamps[0])
    session = Session(folder, cuboids)
    with session.opened():
        assert session.load(stamps[0]).entries[0].detection["label"] == "Truck"  # as saved
        assert session.load(stamps[1]).entries[0].detection["label"] == "Van"  # from cuboids


def test_a_second_session_on_a_folder_is_refused(tmp_path):
    folder, _ = frames_folder(tmp_path)
    with Session(folder).opened():
        with pytest.raises(OutputError, match="another granular run"):
            with Session(folder).opened():
                pass
        result = hostile.run(hostile.tool("granular_tools", "label_cuboids")
                             + ["--frames", folder])
    hostile.assert_fails_clearly(result, 1, str(folder / "labelling_backup"))
    assert "label_cuboids" in result.stderr  # the holder is named


def test_a_folder_that_is_not_frames_is_refused(tmp_path):
    result = hostile.run(hostile.tool("granular_tools", "label_cuboids")
                         + ["--frames", tmp_path])
    hostile.assert_fails_clearly(result, 1, str(tmp_path), "pcd")
    result = hostile.run(hostile.tool("granular_tools", "label_cuboids")
                         + ["--frames", tmp_path / "nowhere"])
    hostile.assert_fails_clearly(result, 1, str(tmp_path / "nowhere"))


def read_only(folder):
    """`folder` made read-only in a way that binds root too (a read-only bind mount); skips
    where this machine cannot."""
    if os.geteuid() != 0:
        for path in [folder, *folder.rglob("*")]:
            if path.is_dir():
                path.chmod(0o555)
        return lambda: [p.chmod(0o755) for p in [folder, *folder.rglob("*")] if p.is_dir()]
    steps = [["mount", "--bind", str(folder), str(folder)],
             ["mount", "-o", "remount,bind,ro", str(folder)]]
    for step in steps:
        done = subprocess.run(step, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            subprocess.run(["umount", str(folder)], capture_output=True, check=False)
            pytest.skip(f"cannot make a read-only mount here: {done.stderr.strip()}")
    return lambda: subprocess.run(["umount", str(folder)], check=True)


def test_a_read_only_folder_is_refused_at_the_start_and_nothing_changes(tmp_path):
    folder, _ = frames_folder(tmp_path)
    (folder / "labelling_backup").mkdir()  # an earlier session's: no write at all is needed
    (folder / "labelling_backup" / ".granular.json").write_text('{"tool": "label_cuboids"}')
    before = hostile.snapshot(folder)
    release = read_only(folder)
    try:
        result = hostile.run(hostile.tool("granular_tools", "label_cuboids")
                             + ["--frames", folder])
    finally:
        release()
    hostile.assert_fails_clearly(result, 1, str(folder), "cannot write")
    assert hostile.snapshot(folder) == before


def test_a_bad_config_is_exit_2_naming_the_key(tmp_path):
    folder, _ = frames_folder(tmp_path)
    config = tmp_path / "labelling.yaml"
    config.write_text("classes:\n  Car: {size: [4.5, 1.8]}\n")
    result = hostile.run(hostile.tool("granular_tools", "label_cuboids")
                         + ["--frames", folder, "--config", config])
    hostile.assert_fails_clearly(result, 2, str(config), "classes.Car.size")


def test_without_a_ros_master_it_says_so_and_leaves_the_folder_free(tmp_path):
    # rospy.init_node would wait for one without end, deaf to SIGINT and SIGTERM.
    folder, _ = frames_folder(tmp_path)
    unused = "http://localhost:9"  # the discard port: nothing answers there
    result = hostile.run(hostile.tool("granular_tools", "label_cuboids") + ["--frames", folder],
                         env=dict(os.environ, ROS_MASTER_URI=unused), timeout=60)
    hostile.assert_fails_clearly(result, 1, "no ROS master", unused)
    with Session(folder).opened():
        pass  # not locked


def test_a_bag_without_boxes_gives_every_cloud_to_label(tmp_path):
    bag = bagmaker.write(tmp_path / "clouds.bag", [
        (CLOUD_TOPIC, bagmaker.cloud(0.0)), (CLOUD_TOPIC, bagmaker.cloud(0.1))])
    frames = tmp_path / "frames"
    assert _prepare_frames(argparse.Namespace(bag=str(bag), frames=str(frames))) == 0
    assert len(list((frames / "pcd").iterdir())) == 2
    assert list((frames / "detections_3d").iterdir()) == []


def test_a_frame_is_found_by_index_from_1_or_by_stamp():
    names = ["1586102742100000000", "1586102742200000000"]
    assert frame_index(names, "2") == 1
    assert frame_index(names, "1586102742100000000") == 0
    assert frame_index(names, "3") is None and frame_index(names, "0") is None


def test_help_tells_what_it_writes():
    result = hostile.run(hostile.tool("granular_tools", "label_cuboids") + ["--help"])
    assert result.status == 0
    assert "labelling_backup" in result.stdout and "Publish Point" in result.stdout


def test_shipped_files_are_where_the_launch_file_finds_them(repo_root):
    launch = (repo_root / "launch" / "label_cuboids.launch").read_text()
    for name in ("labelling.yaml", "labelling.rviz"):
        assert name in launch and (repo_root / "config" / name).is_file()
    rviz = (repo_root / "config" / "labelling.rviz").read_text()
    for topic in ("/label_cuboids/cloud", "/label_cuboids/boxes/update", "/clicked_point"):
        assert topic in rviz
