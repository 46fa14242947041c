"""The simulator's sensor files (--sensor) and parking-lot scene (--scene parking_lot)."""
import dataclasses

import numpy as np
import pytest
import rosbag

from granular_tools.config_loading import ConfigError
from granular_tools.simulation import cli, meshes
from granular_tools.simulation.config import LidarConfig, SimulatorConfig
from granular_tools.simulation.drive import Drive
from granular_tools.simulation.lidar import Lidar, PlacedMesh, Volume
from granular_tools.simulation.sensor import available_sensors, load_sensor

SHIPPED_SENSORS = ["hdl64e", "os1_64", "pandar64", "simulator", "vlp16"]
# Exact geometry: no range noise, no dropouts.
EXACT = LidarConfig(range_noise_sigma=0.0, dropout_probability=0.0)


def sensor_config(name, scene_config=None):
    config = scene_config or SimulatorConfig()
    return dataclasses.replace(config, lidar=load_sensor(name).lidar_config(config.lidar))


def distinct(values, tolerance):
    """The distinct values among `values` (sorted), merging those within `tolerance`."""
    values = np.sort(values)
    starts = np.concatenate([[0], np.nonzero(np.diff(values) > tolerance)[0] + 1])
    return np.array([group.mean() for group in np.split(values, starts[1:])])


def ground(x, y):
    return np.full(np.shape(x), 0.1)


def test_every_shipped_sensor_file_loads_and_the_simulator_file_is_the_default_lidar():
    assert available_sensors() == SHIPPED_SENSORS
    for name in SHIPPED_SENSORS:
        load_sensor(name)
    assert load_sensor("simulator").lidar_config(LidarConfig()) == LidarConfig()


@pytest.mark.parametrize("name", SHIPPED_SENSORS)
def test_sensor_files_rings_and_azimuth_step_show_in_the_cloud(name):
    sensor = load_sensor(name)
    lidar = Lidar(sensor.lidar_config(EXACT))
    # A closed 30 m box around the sensor: every ray returns from one of its walls.
    room = meshes.box((0.0, 0.0, 0.0), (30.0, 30.0, 30.0), meshes.CONCRETE)
    returns = lidar.scan([PlacedMesh(room.vertices, room.faces, room.materials, 0.5)],
                         ground, np.random.default_rng(0))
    x, y, z = returns.points.T
    elevations = distinct(np.degrees(np.arctan2(z, np.hypot(x, y))), 1e-4)
    assert len(elevations) == sensor.rings
    assert elevations[0] == pytest.approx(sensor.min_elevation_deg, abs=1e-4)
    assert elevations[-1] == pytest.approx(sensor.max_elevation_deg, abs=1e-4)
    spacing = (sensor.max_elevation_deg - sensor.min_elevation_deg) / (sensor.rings - 1)
    np.testing.assert_allclose(np.diff(elevations), spacing, atol=1e-4)
    azimuths = distinct(np.degrees(np.arctan2(y, x)) % 360.0, 1e-4)
    assert len(azimuths) == round(360.0 / sensor.azimuth_step_deg)
    # 360 / step rounded to whole returns: within 0.1 % of the file's step (HDL-64E: 2045).
    assert np.diff(azimuths) == pytest.approx(sensor.azimuth_step_deg, rel=1e-3)


def assert_ground_at(points, height):
    """The lowest returns are the ground's, exactly at z = -height (no range noise)."""
    z = points[:, 2]
    assert z.min() == pytest.approx(-height, abs=1e-6)
    assert np.count_nonzero(np.abs(z + height) < 1e-6) > 100


def test_mount_height_puts_the_ground_at_minus_height_and_the_mast_overrides_it():
    config = sensor_config("vlp16")
    config = dataclasses.replace(config, lidar=dataclasses.replace(config.lidar,
                                                                   range_noise_sigma=0.0))
    assert_ground_at(Drive(config, 0.1, seed=1).cloud(0).points, 1.9)
    lot = Drive(config, 0.1, seed=1, scene="parking_lot")
    assert_ground_at(lot.cloud(0).points, config.parking_lot.mast_height)


def test_sensor_file_with_missing_or_unknown_key_or_unknown_name_is_refused(tmp_path, capsys):
    lines = dataclasses.asdict(load_sensor("vlp16")).items()
    text = "".join(f"{key}: {value!r}\n" if isinstance(value, str) else f"{key}: {value}\n"
                   for key, value in lines)
    missing = tmp_path / "missing.yaml"
    missing.write_text(text.replace("rings: 16\n", ""))
    with pytest.raises(ConfigError, match=r"missing.yaml: missing key\(s\) rings"):
        load_sensor(str(missing))
    unknown = tmp_path / "unknown.yaml"
    unknown.write_text(text + "channels: 16\n")
    with pytest.raises(ConfigError, match=r"unknown.yaml: unknown key 'channels'"):
        load_sensor(str(unknown))
    upside_down = tmp_path / "upside_down.yaml"
    upside_down.write_text(text.replace("max_elevation_deg: 15.0", "max_elevation_deg: -20.0"))
    with pytest.raises(ConfigError, match="max_elevation_deg .* must be above"):
        load_sensor(str(upside_down))
    assert cli.main(["--out", str(tmp_path / "x.bag"), "--sensor", "velodyne99"]) == 2
    error = capsys.readouterr().err
    assert "sensor 'velodyne99'" in error and "vlp16" in error
    assert not (tmp_path / "x.bag").exists()


def test_sensor_simulator_writes_the_same_bag_as_no_sensor(tmp_path):
    datas = []
    for name, extra in (("plain", []), ("simulator", ["--sensor", "simulator"])):
        path = tmp_path / f"{name}.bag"
        assert cli.main(["--out", str(path), "--duration", "0.3", "--quiet"] + extra) == 0
        with rosbag.Bag(str(path)) as bag:
            datas.append([bytes(m.data) for _, m, _ in bag.read_messages("/simulator/lidar")])
    assert datas[0] == datas[1]


@pytest.fixture(scope="module")
def lot_bag(tmp_path_factory):
    path = tmp_path_factory.mktemp("lot") / "lot.bag"
    assert cli.main(["--out", str(path), "--scene", "parking_lot", "--duration", "0.3",
                     "--seed", "3", "--quiet"]) == 0
    return path


def test_parking_lot_bag_boxes_every_vehicle_and_pedestrian_and_no_clutter(lot_bag):
    drive = Drive(SimulatorConfig(), 0.3, seed=3, scene="parking_lot")
    labelled = {a.object_id: a.label for a in drive.scene.actors if a.label is not None}
    with rosbag.Bag(str(lot_bag)) as bag:
        messages = [m for _, m, _ in bag.read_messages("/simulator/ground_truth/3d_detections")]
    assert messages
    for message in messages:
        t = message.header.stamp.to_sec() - drive.config.start_time
        boxed = {d.id: d.label for d in message.detections}
        expected = {d.object_id: d.label for d in drive.scene.detections(t)}
        assert boxed == expected
        assert set(boxed.items()) <= set(labelled.items()), "only vehicles and pedestrians"
    labels = {d.label for m in messages for d in m.detections}
    assert "Pedestrian" in labels and {"Sedan", "SUV", "Hatchback", "Jeep"} <= labels
    # Clutter stands where no box is: no trunk, pole, kerb, canopy or hedge centre in a box.
    clutter = [a.centre(0.0) for a in drive.scene.actors if a.label is None]
    clutter += [v.centre for v in drive.scene.volumes]
    assert len(drive.scene.volumes) > 10
    ego = drive.scene.ego_position(0.0)
    for detection in drive.scene.detections(0.0):
        x, y, z, w = detection.quaternion
        yaw = np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
        rotation = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
        local = (np.array(clutter)[:, :2] - (detection.position + ego)[:2]) @ rotation
        assert np.all(np.any(np.abs(local) > detection.size[:2] / 2.0, axis=1))


def test_parking_lot_cars_stand_side_by_side_in_rows_within_the_configured_gaps():
    scene = Drive(SimulatorConfig(), 0.1, seed=2, scene="parking_lot").scene
    gap_low, gap_high = scene.lot.side_gap
    meeting = scene.half_aisle + scene.lot.bay_depth  # where the back-to-back rows meet
    rows = {}
    for actor in scene.actors:
        if actor.label in meshes.VEHICLE_CLASSES and abs(abs(actor.yaw) - np.pi / 2) < 0.2:
            rows.setdefault((np.sign(actor.y), abs(actor.y) < meeting), []).append(actor)
    assert len(rows) == 4
    gaps = []
    for row in rows.values():
        row.sort(key=lambda a: a.x0)
        gaps += [right.x0 - left.x0 - (left.size[1] + right.size[1]) / 2.0
                 for left, right in zip(row, row[1:])]
    gaps = np.array(gaps)
    # Cars in neighbouring bays; an empty bay between two leaves more than a car's width.
    neighbours = gaps[gaps < 1.5]
    assert len(neighbours) > 50
    assert neighbours.min() >= gap_low - 1e-9 and neighbours.max() <= gap_high + 1e-9
    assert np.all(gaps[gaps >= 1.5] > 1.5 + 2 * gap_low)


def ellipsoid_chords(directions, centre, half_size):
    """Length of each ray's chord through an ellipsoid ahead of the sensor, which lies outside
    it (0: the ray misses it)."""
    p, q = -centre / half_size, directions / half_size
    a, b, c = np.sum(q * q, axis=1), 2.0 * q @ p, p @ p - 1.0
    discriminant = b * b - 4.0 * a * c
    ahead = b < 0.0  # both roots (-b -+ sqrt(discriminant)) / 2a positive
    return np.where((discriminant > 0.0) & ahead,
                    np.sqrt(np.maximum(discriminant, 0.0)) / a, 0.0)


def test_canopy_returns_from_inside_its_volume_and_lets_some_rays_pass():
    lidar = Lidar(EXACT)
    canopy = Volume(np.array([10.0, 0.0, 0.0]), np.array([2.0, 2.0, 1.6]), is_box=False,
                    density=0.6)
    # Behind the canopy a closed 40 m box: a ray that passes returns from its wall.
    room = meshes.box((0.0, 0.0, 0.0), (40.0, 40.0, 40.0), meshes.CONCRETE)
    returns = lidar.scan([PlacedMesh(room.vertices, room.faces, room.materials, 0.5)], ground,
                         np.random.default_rng(0), [canopy])
    crossing = ellipsoid_chords(lidar.directions.reshape(-1, 3), canopy.centre,
                                canopy.half_size)
    crossing = crossing[crossing > 0.0]
    ranges = np.linalg.norm(returns.points, axis=1)
    through = ellipsoid_chords(returns.points / ranges[:, None], canopy.centre,
                               canopy.half_size) > 0.0
    radius = np.linalg.norm((returns.points - canopy.centre) / canopy.half_size, axis=1)
    inside = radius <= 1.0 + 1e-9
    passed = np.count_nonzero(through & ~inside) / len(crossing)
    expected = np.mean(np.exp(-canopy.density * crossing))
    assert passed > 0.05 and passed == pytest.approx(expected, abs=0.03)
    # From throughout the volume, not only its surface.
    assert np.count_nonzero(inside) > 200
    assert np.mean(radius[inside] < 0.8) > 0.3


def test_hedge_returns_within_its_first_free_paths():
    lidar = Lidar(EXACT)
    # A hedge 1 m thick across the line of sight, its near face 8 m ahead.
    hedge = Volume(np.array([8.5, 0.0, -1.6]), np.array([0.5, 6.0, 0.7]), is_box=True,
                   density=5.0)
    returns = lidar.scan([], ground, np.random.default_rng(0), [hedge])
    local = np.abs(returns.points - hedge.centre)
    inside = np.all(local <= hedge.half_size + 1e-9, axis=1)
    depth = returns.points[inside, 0] - (hedge.centre[0] - hedge.half_size[0])
    assert np.count_nonzero(inside) > 100
    # Exponential free paths of mean 1 / density = 0.2 m, cut at the far face 1 m in
    # (rays enter at slightly different angles: a few per cent of slack).
    assert np.mean(depth) == pytest.approx(0.2, rel=0.15)
    assert depth.max() <= 1.0 + 1e-9 and np.mean(depth > 0.4) < 0.2


def test_parking_lot_is_reproduced_by_its_seed_and_changed_by_another():
    clouds = [Drive(SimulatorConfig(), 0.2, seed=seed, scene="parking_lot").cloud(1).points
              for seed in (7, 7, 8)]
    np.testing.assert_array_equal(clouds[0], clouds[1])
    assert clouds[0].shape != clouds[2].shape or np.any(clouds[0] != clouds[2])


def test_bad_parking_lot_parameters_or_options_stop_the_tool_naming_them(tmp_path, capsys):
    config = tmp_path / "lot.yaml"
    config.write_text("parking_lot:\n  side_gap: [1.0, 0.4]\n")
    assert cli.main(["--out", str(tmp_path / "x.bag"), "--scene", "parking_lot",
                     "--config", str(config)]) == 2
    assert "parking_lot.side_gap" in capsys.readouterr().err
    # 1 m/s for 200 s would carry the mast out of the 120 m lot.
    assert cli.main(["--out", str(tmp_path / "x.bag"), "--scene", "parking_lot",
                     "--duration", "200"]) == 2
    assert "beyond the lot's length" in capsys.readouterr().err
    assert cli.main(["--out", str(tmp_path / "x.bag"), "--scene", "parking_lot",
                     "--traffic", "2"]) == 2
    assert "--traffic applies to the road scene" in capsys.readouterr().err
    assert not (tmp_path / "x.bag").exists()
