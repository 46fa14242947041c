"""The drive simulator: sensor geometry, shapes, clocks, determinism and bad input."""
import dataclasses
import subprocess

import numpy as np
import pytest
import rosbag

from granular_tools.config_loading import ConfigError, load_yaml_over
from granular_tools.messages import POINT_DTYPE
from granular_tools.simulation import cli, meshes, recorder
from granular_tools.simulation.config import SimulatorConfig
from granular_tools.simulation.drive import Drive

CLOUD_TOPIC = "/simulator/lidar"
DETECTIONS_TOPIC = "/simulator/ground_truth/3d_detections"


def write_box_obj(path, length=4.0, width=2.0, height=1.5):
    """A closed box mesh, deliberately off-centre to check that it gets centred."""
    lines = []
    for x in (0.0, length):
        for y in (0.0, width):
            for z in (0.0, height):
                lines.append(f"v {x + 10.0} {y - 3.0} {z + 1.0}")
    quads = [(1, 2, 4, 3), (5, 7, 8, 6), (1, 5, 6, 2), (3, 4, 8, 7), (1, 3, 7, 5), (2, 6, 8, 4)]
    lines += [f"f {a} {b} {c} {d}" for a, b, c, d in quads]
    path.write_text("\n".join(lines) + "\n")
    return path


def rotation_from_quaternion(x, y, z, w):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def assert_points_on_visible_faces(points, detection, half):
    """Points in the box lie on its faces, and only on faces turned towards the sensor."""
    np.testing.assert_allclose(detection.size, 2 * half, atol=1e-9)
    rotation = rotation_from_quaternion(*detection.quaternion)
    local = (points - detection.position) @ rotation
    inside = local[np.all(np.abs(local) <= half + 0.05, axis=1)]
    sensor = (-detection.position) @ rotation
    # Distance of each point to the planes of the five faces above the road.
    faces = [(0, 1), (0, -1), (1, 1), (1, -1), (2, 1)]
    distance = np.stack([np.abs(inside[:, axis] - sign * half[axis]) for axis, sign in faces])
    assert np.all(distance.min(axis=0) < 0.06), "points off the box's faces"
    nearest = np.argmin(distance, axis=0)
    for face_index, (axis, sign) in enumerate(faces):
        if np.any(nearest == face_index):
            # The face's outward normal points at the sensor: far sides return nothing.
            assert sign * sensor[axis] > half[axis], f"points on hidden face {axis, sign}"
    return len(inside)


def read_bag(path):
    clouds, detections = [], []
    with rosbag.Bag(str(path)) as bag:
        for topic, message, _ in bag.read_messages():
            (clouds if topic == CLOUD_TOPIC else detections).append(message)
    return clouds, detections


def cloud_points(message):
    dtype = POINT_DTYPE
    assert message.point_step == dtype.itemsize
    return np.frombuffer(message.data, dtype=dtype, count=message.width)


@pytest.fixture(scope="module")
def short_bag(tmp_path_factory):
    path = tmp_path_factory.mktemp("bag") / "drive.bag"
    assert cli.main(["--out", str(path), "--duration", "3", "--seed", "5", "--quiet"]) == 0
    return path


def test_cloud_has_lgsvl_fields_and_every_point_is_within_sensor_range(short_bag):
    clouds, _ = read_bag(short_bag)
    assert len(clouds) == 30
    for message in clouds:
        assert message.header.frame_id == "velodyne"
        assert message.height == 1
        assert [(f.name, f.datatype) for f in message.fields] == [
            ("x", 7), ("y", 7), ("z", 7), ("intensity", 2), ("timestamp", 8)]
        points = cloud_points(message)
        ranges = np.linalg.norm(np.stack([points["x"], points["y"], points["z"]], 1), axis=1)
        assert len(points) > 10000
        assert ranges.min() >= 0.5 - 1e-4 and ranges.max() <= 50.0 + 1e-4
        assert points["intensity"].max() > 100, "lane markings and paint reflect strongly"


def test_ground_lies_at_mount_height_below_the_sensor(short_bag):
    clouds, _ = read_bag(short_bag)
    points = cloud_points(clouds[0])
    near = np.hypot(points["x"], points["y"]) < 6.0  # only road within 6 m of the ego
    assert np.median(points["z"][near]) == pytest.approx(-2.3, abs=0.02)


def test_static_box_mesh_yields_points_on_its_visible_faces_only(tmp_path):
    length, width, height = 4.0, 2.0, 1.5
    box_mesh = meshes.load_mesh_file(str(write_box_obj(tmp_path / "box.obj", length, width,
                                                       height)))
    base = SimulatorConfig()
    config = dataclasses.replace(base, traffic=dataclasses.replace(
        base.traffic, class_weights={"Sedan": 1.0}, tilt_noise_deg=0.0, size_variation=0.0))
    drive = Drive(config, duration=1.0, seed=11, class_meshes={"Sedan": box_mesh})
    parked = {a.object_id for a in drive.scene.actors if a.label == "Sedan" and a.speed == 0.0}
    half = np.array([length, width, height]) / 2
    checked = 0
    for index in (0, 9):
        t, points = drive.cloud_times[index], drive.cloud(index).points
        for detection in drive.scene.detections(t):
            if detection.object_id not in parked or np.linalg.norm(detection.position) > 30.0:
                continue
            checked += assert_points_on_visible_faces(points, detection, half)
    assert checked > 200


def test_clouds_and_detections_run_on_their_own_clocks(short_bag):
    clouds, detections = read_bag(short_bag)
    cloud_stamps = np.array([m.header.stamp.to_sec() for m in clouds])
    detection_stamps = np.array([m.header.stamp.to_sec() for m in detections])
    assert np.median(np.diff(cloud_stamps)) == pytest.approx(0.1, abs=0.002)
    assert np.median(np.diff(detection_stamps)) == pytest.approx(0.04, abs=0.003)
    gaps = np.abs(cloud_stamps[:, None] - detection_stamps[None, :]).min(axis=1)
    within_slop = np.count_nonzero(gaps <= 0.01)
    assert 0 < within_slop < len(cloud_stamps), "some clouds pair within 10 ms, not all"
    assert np.all(gaps > 0.0)


def test_moving_box_displacement_grows_with_relative_speed():
    drive = Drive(SimulatorConfig(), duration=2.0, seed=3)
    ego_speed = drive.config.road.ego_speed
    by_id = {a.object_id: a for a in drive.scene.actors}
    t, dt = 1.0, 0.01
    before = {d.object_id: d.position for d in drive.scene.detections(t)}
    after = {d.object_id: d.position for d in drive.scene.detections(t + dt)}
    speeds = set()
    for object_id in before.keys() & after.keys():
        relative_speed = by_id[object_id].speed - ego_speed
        np.testing.assert_allclose(after[object_id] - before[object_id],
                                   [relative_speed * dt, 0.0, 0.0], atol=1e-9)
        speeds.add(round(relative_speed, 3))
    assert len(speeds) >= 3, "oncoming, parked and same-direction traffic all present"


def test_detections_carry_label_id_score_and_forward_speed(short_bag):
    _, detections = read_bag(short_bag)
    labels = set()
    ids_by_label = {}
    for message in detections:
        for detection in message.detections:
            assert detection.score == 1.0
            assert detection.header.frame_id == "velodyne"
            q = detection.bbox.position.orientation
            assert np.linalg.norm([q.x, q.y, q.z, q.w]) == pytest.approx(1.0)
            labels.add(detection.label)
            ids_by_label.setdefault(detection.id, set()).add(detection.label)
    assert labels <= set(meshes.CLASSES)
    assert len(labels) >= 4
    assert all(len(v) == 1 for v in ids_by_label.values()), "ids are stable per object"


def test_same_seed_gives_same_bag_and_other_seed_differs(tmp_path):
    paths = []
    for name, seed in (("a", 4), ("b", 4), ("c", 5)):
        path = tmp_path / f"{name}.bag"
        assert cli.main(["--out", str(path), "--duration", "0.5", "--seed", str(seed),
                         "--quiet"]) == 0
        paths.append(path)
    a, b, c = (read_bag(p) for p in paths)
    assert [m.data for m in a[0]] == [m.data for m in b[0]]
    assert [str(m) for m in a[1]] == [str(m) for m in b[1]]
    assert [m.data for m in a[0]] != [m.data for m in c[0]]


def test_unknown_class_in_mesh_option_is_an_error(tmp_path, capsys):
    mesh = write_box_obj(tmp_path / "box.obj")
    assert cli.main(["--out", str(tmp_path / "x.bag"), "--mesh", f"Tractor={mesh}"]) == 2
    assert "unknown class 'Tractor'" in capsys.readouterr().err
    assert not (tmp_path / "x.bag").exists()


def test_unreadable_mesh_is_an_error_naming_the_file(tmp_path, capsys):
    broken = tmp_path / "broken.stl"
    broken.write_bytes(b"\x00\x01 not a mesh")
    assert cli.main(["--out", str(tmp_path / "x.bag"), "--mesh", f"Sedan={broken}"]) == 2
    assert str(broken) in capsys.readouterr().err
    assert cli.main(["--out", str(tmp_path / "x.bag"),
                     "--mesh", f"Sedan={tmp_path / 'missing.ply'}"]) == 2


def test_unwritable_output_is_an_error(tmp_path, capsys):
    target = tmp_path / "no" / "such" / "folder" / "x.bag"
    assert cli.main(["--out", str(target), "--duration", "0.2", "--quiet"]) == 1
    assert "does not exist" in capsys.readouterr().err


def test_failed_write_leaves_no_bag_under_the_requested_name(tmp_path, monkeypatch):
    drive = Drive(SimulatorConfig(), duration=1.0, seed=1)
    calls = []

    def failing_cloud(index):
        calls.append(index)
        if len(calls) > 3:
            raise RuntimeError("simulated crash")
        return Drive.cloud(drive, index)

    monkeypatch.setattr(drive, "cloud", failing_cloud)
    with pytest.raises(RuntimeError):
        recorder.write_bag(drive, str(tmp_path / "drive.bag"))
    assert list(tmp_path.iterdir()) == []


def test_command_line_help_and_exit_code(tmp_path):
    shown = subprocess.run(["rosrun", "granular_tools", "simulate_drive", "--help"],
                           capture_output=True, text=True, check=True).stdout
    for option in ("--out", "--duration", "--seed", "--traffic", "--mesh", "--config"):
        assert option in shown
    failed = subprocess.run(["rosrun", "granular_tools", "simulate_drive", "--out",
                             str(tmp_path / "x.bag"), "--traffic", "-1"],
                            capture_output=True, text=True)
    assert failed.returncode != 0 and "--traffic" in failed.stderr


def test_shipped_simulator_config_matches_the_defaults(repo_root):
    assert load_yaml_over(SimulatorConfig(), repo_root / "config" / "simulator.yaml") \
        == SimulatorConfig()


def test_config_with_unknown_key_or_wrong_type_names_file_and_key(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("lidar:\n  lazers: 32\n")
    with pytest.raises(ConfigError, match=r"bad.yaml.lidar: unknown key 'lazers'"):
        load_yaml_over(SimulatorConfig(), path)
    path.write_text("lidar:\n  max_range: far\n")
    with pytest.raises(ConfigError, match=r"bad.yaml.lidar.max_range: expected a number"):
        load_yaml_over(SimulatorConfig(), path)
