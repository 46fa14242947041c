"""Hostile inputs through roslaunch and the nodes: the entry points for scripts return the
failing stage's status, arguments are checked before the first stage, relative paths are taken
from where the user stands, and the nodes stop at start-up with a message that says what was
given, what was expected and the path."""
import json
import os
import signal
import socket
import subprocess
import time
import xml.etree.ElementTree as ElementTree

import pytest

import hostile
from conftest import REPO_ROOT
from hostile import (assert_fails_clearly, run, tool, ONLINE_CLASSIFIER, SEGMENT_CLOUD,
                     BAG_TO_FILES_NODE, RUN_PIPELINE)

LAUNCH = [str(REPO_ROOT / "scripts" / "launch")]


def free_port():
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def own_master_environment():
    """An environment whose ROS master (started by roslaunch, or by the ros_master fixture)
    no other test shares."""
    env = dict(os.environ)
    env["ROS_MASTER_URI"] = f"http://localhost:{free_port()}"
    env["ROS_HOME"] = os.environ.get("ROS_HOME", os.path.expanduser("~/.ros"))
    return env


@pytest.fixture(scope="module")
def ros_master():
    env = own_master_environment()
    port = env["ROS_MASTER_URI"].rsplit(":", 1)[1]
    master = subprocess.Popen(["rosmaster", "--core", "-p", port], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    hostile.wait_for(lambda: socket.socket().connect_ex(("localhost", int(port))) == 0, 20,
                     "the ROS master")
    yield env
    master.terminate()
    master.wait(timeout=20)


# --- what roslaunch --ros-args shows ---------------------------------------------------------

@pytest.mark.parametrize("launch", sorted(p.name for p in (REPO_ROOT / "launch").glob("*.launch")))
def test_ros_args_says_which_listed_required_arguments_are_not(launch):
    """roslaunch --ros-args lists an argument whose default is empty, and one derived from
    another, under "Required Arguments" (roslaunch's arg_dump takes an empty default for none):
    their docs must say optional or derived, and every argument must have a doc."""
    declared = {arg.get("name"): arg for arg in
                ElementTree.parse(REPO_ROOT / "launch" / launch).getroot().iter("arg")}
    shown = subprocess.run(["roslaunch", "--ros-args", str(REPO_ROOT / "launch" / launch)],
                           capture_output=True, text=True, timeout=60, check=True).stdout
    assert "undocumented" not in shown, shown
    required = shown.split("Required Arguments:")[1].split("Optional Arguments:")[0] \
        if "Required Arguments:" in shown else ""
    for line in filter(None, (line.strip() for line in required.splitlines())):
        name, doc = line.split(": ", 1)
        arg = declared[name]
        if arg.get("default") is not None or arg.get("value") is not None:
            assert doc.startswith(("optional", "derived from")), line


# --- the nodes, run by hand -------------------------------------------------------------------

NODES = [tool("granular_ros", name) for name in
         ("online_classifier", "segment_cloud", "fit_cuboid_server")] + \
        [tool("granular_tools", name) for name in
         ("bag_to_files_node", "frames_player", "detection_markers", "sensor_frame")]


@pytest.mark.parametrize("node", NODES, ids=lambda command: command[-1].rsplit("/", 1)[-1])
def test_a_node_answers_help_without_a_master(node):
    env = own_master_environment()  # no master runs there: --help must not wait for one
    result = run(node + ["--help"], env=env, timeout=30)
    assert result.status == 0, result
    assert "arameter" in result.stdout, result  # what it reads, not an empty line
    hostile.assert_no_crash(result)


@pytest.mark.parametrize("node", [tool("granular_tools", "bag_to_files_node"),
                                  tool("granular_tools", "sensor_frame")],
                         ids=["bag_to_files_node", "sensor_frame"])
def test_a_python_node_without_a_master_says_so(node, tmp_path):
    # rospy alone retried for ever, deaf to Ctrl-C, or with a private parameter ended in a
    # ConnectionRefusedError traceback.
    result = run(node + [f"_out:={tmp_path / 'out'}"], env=own_master_environment(), timeout=30)
    assert_fails_clearly(result, 1, "no ROS master at http://localhost:")
    assert not (tmp_path / "out").exists()


# --- pipeline.launch and its runner -------------------------------------------------------

def test_the_launch_entry_point_returns_the_failing_stages_status_and_marks_the_run(
        drive, tmp_path):
    frames = tmp_path / "out" / "frames"
    frames.mkdir(parents=True)
    (frames / "thesis.tex").write_text("mine")
    result = run(LAUNCH + [REPO_ROOT / "launch" / "pipeline.launch",
                           f"bag:={drive / 'drive.bag'}", f"out:={tmp_path / 'out'}"],
                 env=own_master_environment())
    assert_fails_clearly(result, 2, frames, "even with overwrite:=true")
    assert (frames / "thesis.tex").read_text() == "mine"
    # A real failure keeps roslaunch's banner, and ends with our line naming the status.
    assert "REQUIRED process [pipeline-" in result.output, str(result)
    assert "launch: required node pipeline failed with exit status 2" in result.output


@pytest.mark.parametrize("options", [[], ["--screen", "-p", "11999"]], ids=["", "options"])
def test_a_misspelt_launch_argument_is_refused_naming_the_closest_declared_one(tmp_path,
                                                                            options):
    """roslaunch ignores an argument its file does not declare: the run went on with the
    default sensor height."""
    result = run(LAUNCH + options + [REPO_ROOT / "launch" / "cuboids.launch", "bag:=test.bag",
                           f"out:={tmp_path / 'c'}", "boxes:=segment", "sensor_hieght:=1.73"],
                 cwd=tmp_path, env=own_master_environment())
    assert_fails_clearly(result, 2, "cuboids.launch takes no argument 'sensor_hieght'",
                         "did you mean sensor_height:=")
    assert "roslaunch" not in result.output and list(tmp_path.iterdir()) == []


def test_the_staging_an_interrupted_launch_removes_is_only_its_own_dead_runs(tmp_path):
    """After a signal, scripts/launch removes the staging its stopped run left under the folders
    its arguments name; never a live run's, an older one's, or a user's file."""
    import sys
    sys.path.insert(0, str(REPO_ROOT / "scripts" / "lib"))
    import launch_status

    out = tmp_path / "out"
    dead = [tmp_path / ".out.partial-999999", out / "models" / ".pictures.partial-999998"]
    kept = [tmp_path / f".out.partial-{os.getpid()}", out / "notes.partial-1.txt",
            tmp_path / "elsewhere" / ".x.partial-999997"]
    for path in dead + kept:
        path.mkdir(parents=True)
    older = out / ".frames.partial-999996"
    older.mkdir()
    os.utime(older, (time.time() - 3600, time.time() - 3600))
    removed = launch_status.remove_staging(["x.launch", f"out:={out}"], time.time() - 60)
    assert sorted(removed) == sorted(map(str, dead))
    assert all(path.exists() for path in kept + [older])


def processes_naming(text):
    """The processes whose command line holds `text`."""
    found = []
    for entry in os.listdir("/proc"):
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as stream:
                command = stream.read().decode(errors="replace")
        except (OSError, ValueError):
            continue
        if entry.isdigit() and text in command:
            found.append(command.replace("\0", " "))
    return found


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_to_the_launch_entry_point_stops_roslaunch_its_nodes_and_their_staging(
        drive, tmp_path, signum):
    """SIGTERM left roslaunch and its nodes running, a staging folder and exit by the signal;
    SIGINT while a stage ran gave exit 0."""
    out = tmp_path / "out"
    process = hostile.start(LAUNCH + [REPO_ROOT / "launch" / "pipeline.launch",
                                      f"bag:={drive / 'drive.bag'}", f"out:={out}",
                                      "n_thresh:=10"], env=own_master_environment())
    result = hostile.interrupt_when(process, lambda: hostile.leftovers(out), signum,
                                    "a stage's staging folder", timeout=120)
    assert result.status == 128 + signum, str(result)
    hostile.assert_no_crash(result)
    assert f"launch: interrupted by {signal.Signals(signum).name}" in result.output
    assert hostile.leftovers(tmp_path) == [], str(result)
    assert processes_naming(str(out)) == []


def test_relative_paths_are_taken_from_where_the_user_stands_and_named_absolutely(tmp_path):
    result = run(LAUNCH + [REPO_ROOT / "launch" / "pipeline.launch", "bag:=drive.bag",
                           "out:=results"], cwd=tmp_path, env=own_master_environment())
    assert_fails_clearly(result, 2, tmp_path / "drive.bag")
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize("argument,named", [
    ("--n-thresh=ten", "ten"), ("--n-thresh=10,-5", "n_thresh"),
    ("--models-from=7", "models_from 7"), ("--models-from=x", "models_from 'x'"),
    ("--model-method=icpp", "icpp"), ("--stages=frames,modles", "modles")])
def test_pipeline_arguments_are_checked_before_the_first_stage(drive, tmp_path, argument,
                                                                named):
    out = tmp_path / "run"
    result = run(RUN_PIPELINE + ["--bag", drive / "drive.bag", "--out", out, argument])
    assert_fails_clearly(result, 2, named)
    assert not (out / "frames").exists()


def test_a_failing_stage_leaves_failed_naming_it_and_no_complete_looking_results(
        drive, tmp_path):
    config_dir = tmp_path / "config"
    config_dir.mkdir()
    (config_dir / "models.yaml").write_text("filters:\n  voxel_grid: {leaf_size: -1}\n")
    out = tmp_path / "run"
    result = run(RUN_PIPELINE + ["--bag", drive / "drive.bag", "--out", out, "--n-thresh", "10",
                                 "--config-dir", config_dir])
    assert_fails_clearly(result, 2, "models", "leaf_size")
    failed = (out / "FAILED").read_text()
    assert "stage: models (build_models)" in failed and "exit status: 2" in failed
    assert not (out / "models").exists()


def test_a_successful_run_removes_an_earlier_failed_marker(drive, tmp_path):
    config_dir = tmp_path / "config"
    config_dir.mkdir()
    (config_dir / "extraction.yaml").write_text("n_thresh: [0]\n")
    out = tmp_path / "run"
    command = RUN_PIPELINE + ["--bag", drive / "drive.bag", "--out", out, "--n-thresh", "10",
                              "--stages", "frames,objects"]
    failed = run(command + ["--config-dir", config_dir])
    assert failed.status == 2 and (out / "FAILED").is_file(), str(failed)
    succeeded = run(command + ["--overwrite"])
    assert succeeded.status == 0, str(succeeded)
    assert not (out / "FAILED").exists()


def many_class_bag(path, common, rare, frames=6):
    """A bag of many classes as a real dataset has them: each `common` class has a box of 150
    points in every frame; each `rare` class one box in one frame, with 15 points half a metre
    apart along its length (a sparse semi-truck, a tram seen once), which the filters empty."""
    import numpy as np
    import bagmaker
    from granular_tools.messages import LabelledBox, detections_message

    rng = np.random.default_rng(7)
    labels = list(common) + list(rare)
    messages = []
    for frame in range(frames):
        detections, points = [], []
        for index, label in enumerate(labels):
            if label in rare and rare.index(label) != frame:
                continue
            centre = np.array([14.0, 6.0 * (index - len(labels) / 2.0), -0.8])
            size = np.array([4.0, 1.8, 1.5]) if label in common else np.array([9.0, 2.5, 1.5])
            detections.append(LabelledBox(300 + index, label, centre, (0.0, 0.0, 0.0, 1.0),
                                          size))
            if label in common:
                points.append(centre + rng.uniform(-0.5, 0.5, size=(150, 3)) * size * 0.95)
            else:
                line = np.zeros((15, 3))
                line[:, 0] = np.linspace(-3.5, 3.5, 15)
                points.append(centre + line)
        stamp = bagmaker.stamp(0.1 * frame)
        messages.append((bagmaker.CLOUD_TOPIC, bagmaker.cloud(0.1 * frame, np.vstack(points),
                                                              frame)))
        messages.append((bagmaker.DETECTIONS_TOPIC,
                         detections_message(detections, stamp, "velodyne", frame)))
    return bagmaker.write(path, messages)


def test_a_many_class_bag_builds_the_models_it_has_data_for_and_names_the_rest(tmp_path):
    """A real dataset's rare classes (a semi-truck seen once, a tram seen once) no longer stop
    the pipeline: the other classes get their models, the rare ones are named as left out."""
    common = ["Car", "Pickup_Truck", "Medium-sized_Truck", "Bus"]
    rare = ["Semi-truck", "Tram_/_Subway"]
    bag = many_class_bag(tmp_path / "many.bag", common, rare)
    out = tmp_path / "results"
    result = run(LAUNCH + [REPO_ROOT / "launch" / "pipeline.launch", f"bag:={bag}",
                           f"out:={out}", "n_thresh:=10"], env=own_master_environment())
    assert result.status == 0, str(result)
    hostile.assert_no_crash(result)
    # A finished run ends with our line, not roslaunch's red "REQUIRED process ... has died!"
    assert "REQUIRED process" not in result.output, str(result)
    assert "launch: done (pipeline finished with exit status 0)" in result.output
    for label in rare:
        assert f"class '{label}' left out" in result.output, str(result)
    document = json.loads((out / "models" / "models.json").read_text(encoding="utf-8"))
    assert sorted(document["left_out"]) == sorted(rare)
    assert all("the filters left no points" in why for why in document["left_out"].values())
    from granular_tools.labels import model_label
    models = sorted(model_label(path) for path in (out / "models").glob("*.pcd"))
    assert models == sorted(common)
    assert len(list((out / "models" / "pictures").glob("*.png"))) == len(common) + 1
    assert not (out / "FAILED").exists()


def test_an_evaluation_of_a_many_class_drive_trains_the_classifiers_on_the_classes_with_models(
        tmp_path):
    """The classifiers learn the classes that got a model, so that every method answers among
    the same classes; the rare ones are left out of both."""
    common = ["Car", "Pickup_Truck", "Bus"]
    rare = ["Semi-truck"]
    bag = many_class_bag(tmp_path / "many.bag", common, rare)
    out = tmp_path / "evaluation"
    result = run(tool("granular_tools", "run_evaluation") + [
        "--train-bag", bag, "--test-bag", bag, "--out", out, "--n-thresh", "10",
        "--methods", "ndt", "--presets", "tuned", "--supervised", "knn"], timeout=600)
    assert result.status == 0, str(result)
    hostile.assert_no_crash(result)
    assert "class 'Semi-truck' left out" in result.output
    assert "knn: trained on 18 objects of 3 classes" in result.output, str(result)
    answers = json.loads((out / "results" / "knn" / "N10.json").read_text())
    assert {o["predictions"]["label"] for o in answers["objects"]} <= set(common)
    assert "- Semi-truck: the filters left no points" in \
        (out / "report" / "index.md").read_text(encoding="utf-8")


# --- the nodes at start-up ------------------------------------------------------------------

def node(command, env, timeout=60):
    """Run a node as /hostile_node. `_name:=value` arguments stay on the parameter server after
    the node ends, so each run clears what the one before left."""
    try:
        return run(command + ["__name:=hostile_node"], env=env, timeout=timeout)
    finally:
        subprocess.run(["rosparam", "delete", "/hostile_node"], env=env, check=False,
                       capture_output=True)


def test_a_models_folder_given_for_a_supervised_method_says_what_is_expected(drive,
                                                                              ros_master):
    result = node(ONLINE_CLASSIFIER + ["_method:=svm", f"_models:={drive / 'models'}"],
                  ros_master)
    assert_fails_clearly(result, 1, drive / "models", "is a folder", "classifier file")


def test_a_classifier_file_given_for_a_registration_method_says_what_is_expected(drive,
                                                                                  ros_master):
    result = node(ONLINE_CLASSIFIER + ["_method:=ndt", f"_models:={drive / 'knn.yml'}"],
                  ros_master)
    assert_fails_clearly(result, 1, drive / "knn.yml", "models folder")


def test_a_truncated_classifier_file_is_named_without_a_parser_dump(drive, tmp_path,
                                                                     ros_master):
    model = tmp_path / "knn.yml"
    raw = (drive / "knn.yml").read_bytes()
    model.write_bytes(raw[: len(raw) // 3])
    result = node(ONLINE_CLASSIFIER + ["_method:=knn", f"_models:={model}"], ros_master)
    assert_fails_clearly(result, 1, model, "not a complete classifier file")
    assert "cv::" not in result.output and "OpenCV(" not in result.output


def test_a_classifier_of_another_method_is_named(drive, ros_master):
    result = node(ONLINE_CLASSIFIER + ["_method:=svm", f"_models:={drive / 'knn.yml'}"],
                  ros_master)
    assert_fails_clearly(result, 1, drive / "knn.yml", "knn")


def test_an_unknown_method_lists_the_known_ones(drive, ros_master):
    result = node(ONLINE_CLASSIFIER + ["_method:=svn", f"_models:={drive / 'knn.yml'}"],
                  ros_master)
    assert_fails_clearly(result, 1, "svn", "svm")


def test_bag_to_files_node_into_a_path_under_a_regular_file_names_it(tmp_path, ros_master):
    blocker = tmp_path / "plain_file"
    blocker.write_text("x")
    result = node(BAG_TO_FILES_NODE + [f"_out:={blocker / 'frames'}"], ros_master)
    assert result.status != 0
    assert_fails_clearly(result, result.status, blocker)
    assert blocker.read_text() == "x"


@pytest.mark.parametrize("node_command,parameter,value,known", [
    (SEGMENT_CLOUD, "methd", "objects", "method"),
    (ONLINE_CLASSIFIER, "min_point", "10", "min_points"),
])
def test_a_node_refuses_a_misspelt_parameter_and_names_the_known_ones(
        drive, ros_master, node_command, parameter, value, known):
    env = dict(ros_master)
    subprocess.run(["rosparam", "set", f"/hostile_node/{parameter}", value], env=env, check=True)
    extra = [] if node_command == SEGMENT_CLOUD else [
        "_method:=knn", f"_models:={drive / 'knn.yml'}"]
    result = node(node_command + extra, env)
    assert_fails_clearly(result, 1, parameter, known)


def test_a_node_parameter_of_the_wrong_type_is_named(ros_master):
    env = dict(ros_master)
    subprocess.run(["rosparam", "set", "/hostile_node/occupancy/cell_size", "fine"], env=env,
                   check=True)
    result = node(SEGMENT_CLOUD, env)
    assert_fails_clearly(result, 1, "cell_size", "expected a number")


def test_play_bag_names_a_truncated_bag(drive, tmp_path):
    bag = tmp_path / "cut.bag"
    raw = (drive / "drive.bag").read_bytes()
    bag.write_bytes(raw[: len(raw) // 2])
    result = run(tool("granular_tools", "play_bag") + [bag, "--quiet"],
                 env=own_master_environment(), timeout=60)
    assert_fails_clearly(result, result.status, bag)
    assert result.status != 0


def test_online_launch_with_exit_when_done_prints_the_latency_summary(drive, tmp_path):
    started = time.monotonic()
    result = run(LAUNCH + [REPO_ROOT / "launch" / "online.launch", f"bag:={drive / 'drive.bag'}",
                           f"models:={drive / 'knn.yml'}", "method:=knn", "rviz:=false",
                           "exit_when_done:=true", "rate:=4"],
                 env=own_master_environment(), timeout=240)
    assert result.status == 0, str(result)
    assert "latency over the whole run" in result.output and "p95" in result.output, \
        str(result)
    assert time.monotonic() - started < 240


def test_online_launch_warns_of_a_cloud_it_skips_and_goes_on(drive, tmp_path):
    """A cloud without x, y, z, then two good ones: the node names what the cloud lacks (once a
    10 s on the wall clock, test_wall_throttle.cpp) and classifies the others."""
    import bagmaker

    messages = []
    for index in range(3):
        t = 0.1 * index
        cloud = bagmaker.cloud_without_xyz(t) if index == 0 else bagmaker.cloud(t, seq=index)
        messages += [(bagmaker.CLOUD_TOPIC, cloud),
                     (bagmaker.DETECTIONS_TOPIC, bagmaker.detections(t, ("Sedan",), index))]
    bag = bagmaker.write(tmp_path / "frames.bag", messages)
    result = run(LAUNCH + [REPO_ROOT / "launch" / "online.launch", f"bag:={bag}",
                           f"models:={drive / 'knn.yml'}", "method:=knn", "rviz:=false",
                           "exit_when_done:=true"],
                 env=own_master_environment(), timeout=120)
    assert result.status == 0, str(result)
    assert "online_classifier: skipping a cloud: the cloud has no float32 field 'x'" in \
        result.output, str(result)
    assert "latency over the whole run: 2 frames" in result.output, str(result)


def test_online_launch_with_a_models_folder_for_svm_ends_without_a_traceback(drive):
    """The node's fatal message was clear, then roslaunch's shutdown made the bag player print
    a KeyboardInterrupt traceback."""
    result = run(LAUNCH + [REPO_ROOT / "launch" / "online.launch", f"bag:={drive / 'drive.bag'}",
                           f"models:={drive / 'models'}", "method:=svm", "rviz:=false",
                           "exit_when_done:=true"],
                 env=own_master_environment(), timeout=120)
    assert_fails_clearly(result, 1, drive / "models", "svm")
    assert "KeyboardInterrupt" not in result.output


def test_online_launch_on_renamed_topics_names_the_bags_topics_and_the_arguments(drive):
    """A bag whose topics are renamed: the warning said only "nothing on /simulator/lidar"."""
    process = hostile.start(LAUNCH + [
        REPO_ROOT / "launch" / "online.launch", f"bag:={drive / 'drive.bag'}",
        f"models:={drive / 'knn.yml'}", "method:=knn", "rviz:=false", "loop:=true",
        "cloud_topic:=/velodyne_points"], env=own_master_environment())

    def warned():
        # pread: the launch writes at the files' shared offset, which a seek would move.
        output = b"".join(os.pread(stream.fileno(), os.fstat(stream.fileno()).st_size, 0)
                          for stream in process.streams)
        return b"nothing on /velodyne_points" in output

    result = hostile.interrupt_when(process, warned, signal.SIGINT, "the silent topic's warning",
                                    timeout=60)
    assert "topics published now: /simulator/lidar" in result.output, str(result)
    assert "cloud_topic:=" in result.output
    assert result.status == 130, str(result)
    hostile.assert_no_crash(result)
