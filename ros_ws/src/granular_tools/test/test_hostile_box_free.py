"""Hostile inputs through the box-free tools (fit_cuboids, evaluate_segmentation, run_cuboids,
online.launch boxes:=segment) and the labelling documents: clouds with no points, all NaN, one
ring, a billion-metre point; frames whose ground cannot be found (a wall filling the view, an
empty scene); clouds not in the sensor's frame (a cloud 50 m below the sensor, a drive shifted
and tilted as a world frame has it); a detections document edited by hand into nonsense. Each
case: exit 0 with every frame written and the culprit named, or a clear one-line error;
nothing half written."""
import json

import numpy as np
import pytest

import bagmaker
import hostile
from bagmaker import CLOUD_TOPIC, DETECTIONS_TOPIC
from conftest import REPO_ROOT
from hostile import assert_no_crash, leftovers, run, tool, BAG_TO_FILES, EXTRACT

FIT_CUBOIDS = tool("granular_ros", "fit_cuboids")
EVALUATE_SEGMENTATION = tool("granular_ros", "evaluate_segmentation")
RUN_CUBOIDS = tool("granular_tools", "run_cuboids")
SIMULATOR = ["--sensor-height", "2.3", "--azimuth-step", "1"]


def ground_scene(rng, z=-2.3):
    """A road at height `z` (m, in the sensor's frame) with a car on it 10 m ahead."""
    road = np.c_[rng.uniform(-30, 30, size=(4000, 2)), np.full(4000, z)]
    car = np.array([10.0, 0.0, z + 0.75]) + rng.uniform(-0.5, 0.5, (300, 3)) * [4.4, 1.8, 1.5]
    return np.vstack([road, car])


def hostile_clouds():
    """Name -> cloud (sensor frame, m): each a frame of the bag."""
    rng = np.random.default_rng(1)
    angles = np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)
    return {
        "empty": np.zeros((0, 3)),
        "all_nan": np.full((500, 3), np.nan),
        "one_ring": np.c_[8.6 * np.cos(angles), 8.6 * np.sin(angles), np.full(360, -2.3)],
        "billion_metres": np.vstack([ground_scene(rng), [[1e9, 0.0, 0.0]]]),
        "wall": np.c_[np.full(3000, 3.0), rng.uniform(-10, 10, 3000), rng.uniform(-2.3, 5, 3000)],
        "road": ground_scene(rng),
    }


@pytest.fixture(scope="module")
def hostile_frames(tmp_path_factory):
    """(the bag, its frames folder, name -> stamp): one frame per hostile cloud, each with a
    Sedan box."""
    folder = tmp_path_factory.mktemp("box_free")
    messages, stamps = [], {}
    for index, (name, points) in enumerate(hostile_clouds().items()):
        t = 0.1 * index
        stamp = bagmaker.stamp(t)
        stamps[name] = f"{stamp.secs}{stamp.nsecs:09d}"
        messages.append((CLOUD_TOPIC, bagmaker.cloud(t, points, index)))
        messages.append((DETECTIONS_TOPIC, bagmaker.detections(t, ("Sedan",), index)))
    bag = bagmaker.write(folder / "hostile.bag", messages)
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", folder / "frames", "--quiet"])
    assert result.status == 0, str(result)
    return bag, folder / "frames", stamps


# Why each frame without ground is named; the others must not be.
NO_GROUND = {"empty": "no points, so no ground",
             "all_nan": "all 500 points are NaN or infinite",
             "wall": "no ground plane found among 3000 points (the lowest at z = -2.30 m"}


def assert_names_the_frames_without_ground(result, stamps, prefix=""):
    for name, why in NO_GROUND.items():
        assert f"{prefix}{stamps[name]}: {why}" in result.output, f"{name}\n{result}"
    for name in set(stamps) - set(NO_GROUND):
        assert f"{stamps[name]}: no" not in result.output, f"{name}\n{result}"


@pytest.mark.parametrize("boxes", ["segment", "detections"])
def test_fit_cuboids_fits_every_frame_and_names_those_without_ground(hostile_frames, tmp_path,
                                                                    boxes):
    _, frames, stamps = hostile_frames
    out = tmp_path / "cuboids"
    result = run(FIT_CUBOIDS + ["--frames", frames, "--out", out, "--boxes", boxes] + SIMULATOR)
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert_names_the_frames_without_ground(result, stamps)
    # Every frame written, none half: a cuboids file per cloud, each standard JSON.
    written = sorted(path.stem for path in out.glob("[!.]*.json"))
    assert written == sorted(stamps.values())
    for path in out.glob("[!.]*.json"):
        json.loads(path.read_text(), parse_constant=lambda name: pytest.fail(f"{name} in JSON"))
    assert leftovers(tmp_path) == []


def test_evaluate_segmentation_names_the_frames_without_ground(hostile_frames, tmp_path):
    _, frames, stamps = hostile_frames
    result = run(EVALUATE_SEGMENTATION + ["--frames", frames, "--save", tmp_path / "seen"]
                 + SIMULATOR)
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert_names_the_frames_without_ground(result, stamps, "warning: frame without ground: ")
    assert len(list((tmp_path / "seen").glob("[!.]*.pcd"))) == len(stamps)
    assert leftovers(tmp_path) == []


def test_extract_objects_names_the_cloud_without_a_finite_point(hostile_frames, tmp_path):
    _, frames, stamps = hostile_frames
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert f"{stamps['all_nan']}.pcd: all 500 points are NaN or infinite" in result.output
    assert leftovers(tmp_path) == []


def test_run_cuboids_on_the_hostile_bag_ends_with_every_frame_and_the_frames_named(
        hostile_frames, tmp_path):
    bag, _, stamps = hostile_frames
    out = tmp_path / "run"
    result = run(RUN_CUBOIDS + ["--bag", bag, "--out", out] + SIMULATOR)
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert_names_the_frames_without_ground(result, stamps)
    assert len(list((out / "cuboids").glob("[!.]*.json"))) == len(stamps)
    assert leftovers(tmp_path) == []


def test_cuboids_launch_on_the_hostile_bag_ends_well_naming_the_frames_without_ground(
        hostile_frames, tmp_path):
    from test_hostile_launch import LAUNCH, own_master_environment

    bag, _, stamps = hostile_frames
    out = tmp_path / "run"
    result = run(LAUNCH + [REPO_ROOT / "launch" / "cuboids.launch", f"bag:={bag}", f"out:={out}"],
                 env=own_master_environment(), timeout=120)
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert "launch: done (cuboids finished with exit status 0)" in result.output, str(result)
    assert_names_the_frames_without_ground(result, stamps)
    assert len(list((out / "cuboids").glob("[!.]*.json"))) == len(stamps)
    assert leftovers(tmp_path) == []


def test_online_launch_segmenting_the_hostile_bag_names_a_frame_without_ground(hostile_frames,
                                                                              drive):
    from test_hostile_launch import LAUNCH, own_master_environment

    bag, _, _ = hostile_frames
    result = run(LAUNCH + [REPO_ROOT / "launch" / "online.launch", f"bag:={bag}",
                           f"models:={drive / 'knn.yml'}", "method:=knn", "boxes:=segment",
                           "rviz:=false", "exit_when_done:=true"],
                 env=own_master_environment(), timeout=120)
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert "no points, so no ground" in result.output, str(result)


# --- clouds not in the sensor's frame ---------------------------------------------------------

def frames_of(folder, clouds, frame_id="velodyne"):
    """A frames folder of `clouds` (name -> points, one frame each, a Sedan box each) whose
    clouds and boxes are in `frame_id`; returns (folder, name -> stamp)."""
    messages, stamps = [], {}
    for index, (name, points) in enumerate(clouds.items()):
        t = 0.1 * index
        stamp = bagmaker.stamp(t)
        stamps[name] = f"{stamp.secs}{stamp.nsecs:09d}"
        cloud = bagmaker.cloud(t, points, index)
        boxes = bagmaker.detections(t, ("Sedan",), index)
        cloud.header.frame_id = boxes.header.frame_id = frame_id
        for detection in boxes.detections:
            detection.header.frame_id = frame_id
        messages += [(CLOUD_TOPIC, cloud), (DETECTIONS_TOPIC, boxes)]
    bag = bagmaker.write(folder / "frames.bag", messages)
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", folder / "frames", "--quiet"])
    assert result.status == 0, str(result)
    return folder / "frames", stamps


OTHER_FRAME_TOOLS = {
    "fit_cuboids segment": (FIT_CUBOIDS + ["--boxes", "segment", "--out"], "cuboids"),
    "fit_cuboids detections": (FIT_CUBOIDS + ["--boxes", "detections", "--out"], "cuboids"),
    "evaluate_segmentation": (EVALUATE_SEGMENTATION + ["--save"], "seen"),
}


@pytest.mark.parametrize("tool_name", sorted(OTHER_FRAME_TOOLS))
def test_a_cloud_50_m_below_the_sensor_is_refused_naming_its_frame_and_the_remedy(tmp_path,
                                                                                 tool_name):
    """It was segmented above its road, 50 m too low for the sensor, without a word."""
    rng = np.random.default_rng(1)
    frames, stamps = frames_of(tmp_path, {"road": ground_scene(rng),
                                          "50_m_below": ground_scene(rng, z=-52.3)})
    command, out = OTHER_FRAME_TOOLS[tool_name]
    result = run(command + [tmp_path / out, "--frames", frames] + SIMULATOR)
    hostile.assert_fails_clearly(
        result, 1, f"{stamps['50_m_below']}: the road lies at z = -52.",
        " m under the sensor, tilted 0.0 deg, where the sensor's frame has it at z = -2.30 m",
        "in frame 'velodyne', looks like a world or vehicle frame", "a static transform from "
        "'velodyne' to the sensor", "--sensor auto", "--allow-other-frames")
    assert not (tmp_path / out).exists()
    assert leftovers(tmp_path) == []

    # The override goes on, naming the frame among those without ground; the road is not named.
    result = run(command + [tmp_path / out, "--frames", frames, "--allow-other-frames"]
                 + SIMULATOR)
    assert result.status == 0, str(result)
    assert f"{stamps['50_m_below']}: the road lies at z = -52." in result.output
    assert f"{stamps['road']}:" not in result.output, str(result)
    assert len(list((tmp_path / out).glob("[!.]*.json"))) == 2


def test_run_cuboids_stops_at_a_cloud_50_m_below_the_sensor_unless_told_to_go_on(tmp_path):
    rng = np.random.default_rng(1)
    _, stamps = frames_of(tmp_path, {"road": ground_scene(rng),
                                     "50_m_below": ground_scene(rng, z=-52.3)})
    bag = tmp_path / "frames.bag"
    result = run(RUN_CUBOIDS + ["--bag", bag, "--out", tmp_path / "run"] + SIMULATOR)
    hostile.assert_fails_clearly(result, 1, f"{stamps['50_m_below']}: the road lies at z = -52.",
                                 "cuboids (fit_cuboids): failed with exit status 1")
    assert not (tmp_path / "run" / "cuboids").exists()
    result = run(RUN_CUBOIDS + ["--bag", bag, "--out", tmp_path / "run", "--overwrite",
                                "--allow-other-frames"] + SIMULATOR)
    assert result.status == 0, str(result)
    assert f"{stamps['50_m_below']}: the road lies at z = -52." in result.output
    assert len(list((tmp_path / "run" / "cuboids").glob("[!.]*.json"))) == 2
    assert leftovers(tmp_path) == []


def test_online_launch_segmenting_a_cloud_50_m_below_the_sensor_warns_naming_its_frame(
        tmp_path, drive):
    from test_hostile_launch import LAUNCH, own_master_environment

    rng = np.random.default_rng(1)
    frames_of(tmp_path, {"50_m_below": ground_scene(rng, z=-52.3)}, frame_id="odom")
    result = run(LAUNCH + [REPO_ROOT / "launch" / "online.launch",
                           f"bag:={tmp_path / 'frames.bag'}", f"models:={drive / 'knn.yml'}",
                           "method:=knn", "boxes:=segment", "sensor_height:=2.3", "rviz:=false",
                           "exit_when_done:=true"],
                 env=own_master_environment(), timeout=120)
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert "segment_cloud: the cloud of " in result.output, str(result)
    assert "in frame 'odom': the road lies at z = -52." in result.output, str(result)
    assert "a static transform from 'odom' to the sensor" in result.output


def test_a_drive_shifted_and_tilted_as_a_world_frame_is_refused_naming_the_frame(drive,
                                                                                tmp_path):
    """The simulated drive's clouds as a world frame would give them: the road at z = 0 (the
    sensor 2.3 m above it) and leaning a little more each frame; the boxes in frame 'odom'."""
    import shutil

    from granular_tools.pcd import read_pcd

    frames = tmp_path / "frames"
    shutil.copytree(drive / "frames", frames)
    clouds = sorted((frames / "pcd").glob("[!.]*.pcd"))
    for index, path in enumerate(clouds):
        raw = path.read_bytes()
        points = read_pcd(path)[1].copy()
        pitch = np.radians(2.0 * index)
        x, z = points["x"].astype(float), points["z"].astype(float)
        points["x"] = np.cos(pitch) * x + np.sin(pitch) * z
        points["z"] = -np.sin(pitch) * x + np.cos(pitch) * z + 2.3
        data = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
        path.write_bytes(raw[:data] + points.tobytes())
    for path in (frames / "detections_3d").glob("[!.]*.json"):
        document = json.loads(path.read_text())
        document["header"]["frame_id"] = "odom"
        path.write_text(json.dumps(document))
    first = clouds[0].stem
    for command, out in OTHER_FRAME_TOOLS.values():
        result = run(command + [tmp_path / out, "--frames", frames] + SIMULATOR)
        hostile.assert_fails_clearly(result, 1, f"{first}: the road lies at z = 0.00 m under the "
                                     "sensor", "in frame 'odom'", "a static transform from 'odom'")
        assert not (tmp_path / out).exists()
    # The same frames in the sensor's frame: no frame named.
    result = run(FIT_CUBOIDS + ["--frames", drive / "frames", "--out", tmp_path / "sensor"]
                 + SIMULATOR)
    assert result.status == 0 and "frames without ground" not in result.output, str(result)
    assert leftovers(tmp_path) == []


# --- the labelling tool's fit service (fit_cuboid_server, label_cuboids' new boxes) -----------

def write_xyz_pcd(path, xyz):
    xyz = np.asarray(xyz, np.float32).reshape(-1, 3)
    header = ("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
              f"WIDTH {len(xyz)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(xyz)}\n"
              "DATA binary\n")
    path.write_bytes(header.encode() + xyz.tobytes())
    return path


@pytest.fixture(scope="module")
def fit_service(tmp_path_factory):
    """fit_cuboid_server on its own master; yields (call(cloud_file, click) -> reply, folder)."""
    import os
    import subprocess

    import rosgraph
    import rospy
    from geometry_msgs.msg import Point, Vector3
    from granular_ros.srv import FitCuboid
    from test_hostile_launch import own_master_environment

    env = own_master_environment()
    port = env["ROS_MASTER_URI"].rsplit(":", 1)[1]
    master = subprocess.Popen(["rosmaster", "--core", "-p", port], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    server = subprocess.Popen(tool("granular_ros", "fit_cuboid_server"), env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    saved = os.environ.get("ROS_MASTER_URI")
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    try:
        def service_up():  # rospy's wait_for_service needs init_node for its timeout
            try:
                rosgraph.Master("/hostile").lookupService("/fit_cuboid")
                return True
            except Exception:  # the master not up yet, or the service not registered
                return False

        hostile.wait_for(service_up, 60, "the fit service")
        proxy = rospy.ServiceProxy("fit_cuboid", FitCuboid)

        def call(cloud_file, click):
            reply = proxy(cloud_file=str(cloud_file), click=Point(*click), label="Sedan",
                          size=Vector3(4.5, 1.8, 1.5))
            assert server.poll() is None, "the fit service died"
            return reply

        yield call, tmp_path_factory.mktemp("fit_service")
    finally:
        if saved is None:
            os.environ.pop("ROS_MASTER_URI", None)
        else:
            os.environ["ROS_MASTER_URI"] = saved
        server.terminate()
        server.wait(timeout=20)
        master.terminate()
        master.wait(timeout=20)


FIT_SERVICE_REFUSALS = {
    "an empty cloud": ("empty", (10.0, 0.0, -1.5),
                       "the cloud has no finite point: nothing to fit a box to"),
    "a cloud all NaN": ("all_nan", (10.0, 0.0, -1.5),
                        "the cloud has no finite point: nothing to fit a box to"),
    "a NaN click": ("scene", (float("nan"), 0.0, -1.5),
                    "the click (nan, 0, -1.5) is not finite: no box"),
    "a click far from every point": ("scene", (1e6, 0.0, 0.0),
                                     "the click (1e+06, 0, 0) is 999970.0 m from the nearest "
                                     "point of the cloud, farther than click.ground_radius "
                                     "(6.0 m): click on the cloud"),
    "a cloud file that vanished": ("missing", (10.0, 0.0, -1.5), "cannot read: No such file or directory"),
}


@pytest.mark.parametrize("case", sorted(FIT_SERVICE_REFUSALS))
def test_the_fit_service_refuses_a_box_it_cannot_place_naming_the_file_and_the_click(
        fit_service, case):
    """An empty cloud, a cloud of NaN or a click away from the cloud gave a box of the class's
    size standing at the click's own height (rviz's grid: the sensor's); a NaN click was
    "box centre is not finite"."""
    call, folder = fit_service
    name, click, why = FIT_SERVICE_REFUSALS[case]
    files = {"empty": lambda path: write_xyz_pcd(path, np.zeros((0, 3))),
             "all_nan": lambda path: write_xyz_pcd(path, np.full((100, 3), np.nan)),
             "scene": lambda path: write_xyz_pcd(path, ground_scene(np.random.default_rng(1))),
             "missing": lambda path: path}
    cloud_file = files[name](folder / f"{name}.pcd")
    reply = call(cloud_file, click)
    assert reply.error == f"{cloud_file}: {why}"
    assert reply.points == 0


def test_the_fit_service_fits_a_car_in_a_huge_cloud(fit_service):
    """Two million points around a car: the box is fitted to the car, the service still up."""
    call, folder = fit_service
    rng = np.random.default_rng(4)
    clutter = np.c_[rng.uniform(-80, 80, (2_000_000, 2)), np.full(2_000_000, -2.3)]
    car = np.array([10.0, 0.0, -1.55]) + rng.uniform(-0.5, 0.5, (300, 3)) * [4.4, 1.8, 1.5]
    cloud_file = write_xyz_pcd(folder / "huge.pcd", np.vstack([clutter, car]))
    reply = call(cloud_file, (10.0, 0.0, -1.5))
    assert reply.error == "" and reply.points > 200, reply
    centre = reply.cuboid.bbox.position.position
    assert abs(centre.x - 10.0) < 0.3 and abs(centre.y) < 0.3, reply


# --- a detections document edited by hand into nonsense ---------------------------------------

KITTI_LABELS = tool("granular_tools", "kitti_labels")


def edited_frames(frames, target, nan=False):
    """A copy of `frames` whose last detections document was edited by hand: a box of zero size
    (id 201), a copy of the first box (its id twice), a label with a newline (id 202) and, with
    `nan`, a NaN in the first box's orientation (a yaw typed as NaN). Returns (copy, document)."""
    import copy
    import shutil

    shutil.copytree(frames, target)
    path = sorted((target / "detections_3d").glob("[!.]*.json"))[-1]
    document = json.loads(path.read_text())
    first = document["detections"][0]
    zero = copy.deepcopy(first)
    zero["id"], zero["bbox"]["size"] = 201, {"x": 0.0, "y": 0.0, "z": 0.0}
    newline = copy.deepcopy(first)
    newline["id"], newline["label"] = 202, "Sedan\nCar"
    document["detections"] += [zero, copy.deepcopy(first), newline]
    if nan:
        first["bbox"]["position"]["orientation"]["z"] = float("nan")
    path.write_text(json.dumps(document))  # NaN written as Python writes it: not JSON
    return target, path


def test_a_document_edited_into_nonsense_has_each_box_named_and_the_rest_used(hostile_frames,
                                                                             tmp_path):
    frames, document = edited_frames(hostile_frames[1], tmp_path / "frames")
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert f"{document}: detections[1] (id 201, Sedan): box size must be finite and positive" \
        in result.output, str(result)
    assert f"{document}: detection id 100 is given to 2 boxes" in result.output

    result = run(FIT_CUBOIDS + ["--frames", frames, "--out", tmp_path / "cuboids", "--boxes",
                                "detections"] + SIMULATOR)
    assert result.status == 0, str(result)
    assert "(id 201, Sedan): box size must be finite and positive" in result.output

    # The KITTI files are whitespace-separated lines: the newline is encoded, in the summary too.
    result = run(KITTI_LABELS + ["export", frames, "--out", tmp_path / "labels"])
    assert result.status == 0, str(result)
    assert "Sedan%0ACar 1" in result.output and "a box with a zero or negative size 1" in \
        result.output, str(result)
    lines = (tmp_path / "labels" / f"{document.stem}.txt").read_text().splitlines()
    assert [line.split(" ")[0] for line in lines] == ["Sedan", "Sedan", "Sedan%0ACar"]
    assert leftovers(tmp_path) == []


def test_a_nan_typed_into_a_document_is_refused_naming_the_file(hostile_frames, tmp_path):
    frames, document = edited_frames(hostile_frames[1], tmp_path / "frames", nan=True)
    for command, out in ((EXTRACT + ["--in", frames, "--out"], "objects"),
                         (FIT_CUBOIDS + SIMULATOR + ["--boxes", "detections", "--frames", frames,
                                                     "--out"], "cuboids"),
                         (KITTI_LABELS + ["export", frames, "--out"], "labels")):
        result = run(command + [tmp_path / out])
        hostile.assert_fails_clearly(result, 1, document, "not valid JSON")
        assert not (tmp_path / out).exists()
    assert leftovers(tmp_path) == []


def test_evaluate_cuboids_says_why_it_skipped_true_boxes_of_a_nonsense_document(
        hostile_frames, tmp_path):
    """It said only "reasons in summary.json"."""
    frames, _ = edited_frames(hostile_frames[1], tmp_path / "frames", nan=True)
    result = run(tool("granular_tools", "evaluate_cuboids") + [
        "--truth", frames, "--predicted", hostile_frames[1] / "detections_3d", "--out",
        tmp_path / "report"])
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert "boxes skipped as invalid: 2 true (1 a box with NaN or infinite numbers, 1 a box " \
           "with a zero or negative size), 0 predicted" in result.output, str(result)


# --- KITTI folders with clouds of no use ---------------------------------------------------------

def test_kitti_velodyne_files_without_a_finite_point_are_named_and_the_rest_converted(
        kitti_fixture, tmp_path):
    """An empty velodyne file and one of NaN became frames without a word (fit_cuboids then
    found no ground in them); a billion-metre point is a point like any other."""
    import shutil

    folder = tmp_path / "kitti"
    for sub in ("velodyne", "label_2", "calib"):
        (folder / sub).mkdir(parents=True)
        for path in sorted((kitti_fixture / sub).glob("00000[0-3].*")):
            shutil.copy(path, folder / sub / path.name)
    velodyne = folder / "velodyne"
    (velodyne / "000001.bin").write_bytes(b"")
    np.full((100, 4), np.nan, np.float32).tofile(velodyne / "000002.bin")
    far = np.fromfile(velodyne / "000003.bin", np.float32).reshape(-1, 4)
    far[0, :3] = (1e9, 0.0, 0.0)
    far.tofile(velodyne / "000003.bin")
    result = run(tool("granular_tools", "kitti_to_bag") + [folder, "--out", tmp_path / "k.bag"])
    assert result.status == 0, str(result)
    assert_no_crash(result)
    assert f"warning: {velodyne / '000001.bin'}: no points" in result.output
    assert f"warning: {velodyne / '000002.bin'}: all 100 points are NaN or infinite" in \
        result.output
    assert "000003.bin" not in result.output and "4 frames" in result.output
    frames = tmp_path / "frames"
    assert run(BAG_TO_FILES + ["--bag", tmp_path / "k.bag", "--out", frames,
                               "--quiet"]).status == 0
    result = run(FIT_CUBOIDS + ["--frames", frames, "--out", tmp_path / "cuboids"])
    assert result.status == 0, str(result)
    assert "frames without ground (2)" in result.output, str(result)
    assert len(list((tmp_path / "cuboids").glob("[!.]*.json"))) == 4
