"""The install space: `catkin_make install`'s files, put under a temporary root, run a launch
file by package name with nothing of the source tree or the devel space in the environment:
roslaunch granular_tools cuboids.launch on a short simulated drive, as a deployed workspace (a
robot, a container) would. The launch file reads the installed config/, fit_cuboids the
installed sensor files."""
import json
import os
import socket
import subprocess

import pytest

import hostile
from conftest import REPO_ROOT

BUILD = REPO_ROOT / "ros_ws" / "build"
RUN_CUBOIDS = hostile.tool("granular_tools", "run_cuboids")


def free_port():
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def install_prefix():
    """CMAKE_INSTALL_PREFIX of the catkin_make build (ros_ws/install unless configured)."""
    for line in (BUILD / "CMakeCache.txt").read_text().splitlines():
        if line.startswith("CMAKE_INSTALL_PREFIX:"):
            return line.split("=", 1)[1]
    raise AssertionError(f"{BUILD / 'CMakeCache.txt'} names no CMAKE_INSTALL_PREFIX")


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The install space as `catkin_make install` writes it, under a temporary DESTDIR (the
    built workspace's files; nothing is built here)."""
    root = tmp_path_factory.mktemp("install_root")
    result = hostile.run(["cmake", "--install", BUILD], env={**os.environ, "DESTDIR": str(root)})
    assert result.status == 0, str(result)
    prefix = root / install_prefix().lstrip("/")
    assert (prefix / "setup.bash").is_file(), str(result)
    return prefix


def in_install_space(prefix, command, cwd, timeout=300):
    """`command` in a shell that sourced only the install space: no ROS_PACKAGE_PATH,
    PYTHONPATH or library path of the source tree or the devel space; its own ROS master."""
    port = free_port()
    env = {"PATH": "/usr/bin:/bin", "HOME": os.environ["HOME"],
           "ROS_HOME": str(cwd / "ros_home"), "ROS_MASTER_URI": f"http://localhost:{port}",
           "LANG": "C.UTF-8"}
    script = f'source "{prefix}/setup.bash" && {command}'
    return subprocess.run(["bash", "-c", script], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=timeout)


def test_ros_finds_the_installed_packages_and_their_files(installed, tmp_path):
    found = in_install_space(installed, "rospack find granular_tools && rospack find granular_ros",
                             tmp_path)
    assert found.returncode == 0, found.stderr
    assert found.stdout.split() == [str(installed / "share" / "granular_tools"),
                                    str(installed / "share" / "granular_ros")]
    share = installed / "share"

    def names(folder, pattern="*"):
        return sorted(path.name for path in folder.glob(pattern) if path.is_file())

    assert names(share / "granular_tools" / "launch") == names(REPO_ROOT / "launch", "*.launch")
    assert names(share / "granular_tools" / "config") == names(REPO_ROOT / "config")
    assert names(share / "granular_ros" / "config" / "sensors") \
        == names(REPO_ROOT / "config" / "sensors")


def test_a_launch_file_runs_by_package_name_from_the_install_space(installed, tmp_path):
    # The installed simulator renders with a sensor file by name (the installed one), and
    # cuboids.launch fits the box-free segments with the installed config and sensor files.
    made = in_install_space(
        installed, "rosrun granular_tools simulate_drive --out drive.bag --duration 4 --seed 3 "
                   "--sensor simulator --quiet", tmp_path)
    assert made.returncode == 0, made.stderr
    launched = in_install_space(
        installed, "roslaunch granular_tools cuboids.launch bag:=drive.bag out:=installed "
                   "max_range:=30 min_points:=50", tmp_path)
    assert launched.returncode == 0, launched.stdout + launched.stderr
    installed_out = tmp_path / "installed"
    assert not (installed_out / "FAILED").exists(), launched.stdout + launched.stderr
    # The same bag through the devel space's runner and the source tree's config: the same
    # cuboids, byte for byte, and the same scores.
    source = hostile.run(RUN_CUBOIDS + ["--bag", tmp_path / "drive.bag", "--out",
                                        tmp_path / "source", "--config-dir",
                                        REPO_ROOT / "config", "--max-range", "30",
                                        "--min-points", "50"])
    assert source.status == 0, str(source)
    fitted = sorted(path.name for path in (installed_out / "cuboids").glob("[!.]*.json"))
    assert fitted == sorted(
        path.name for path in (tmp_path / "source" / "cuboids").glob("[!.]*.json"))
    assert len(fitted) == len(list((installed_out / "frames" / "pcd").glob("*.pcd"))) > 0
    for name in fitted:
        assert (installed_out / "cuboids" / name).read_bytes() \
            == (tmp_path / "source" / "cuboids" / name).read_bytes(), name
    scores = [json.loads((out / "report" / "summary.json").read_text())["overall"]
              for out in (installed_out, tmp_path / "source")]
    assert scores[0] == scores[1]
    # The session's drive through run_cuboids: recall over 0.7 (test_run_cuboids).
    assert scores[0]["criteria"]["paper"]["recall"] > 0.7
