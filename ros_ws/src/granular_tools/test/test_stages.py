"""The runners call each tool by its own path, not through rosrun's slow look-up, and get the
executable rosrun would run."""
import subprocess

from granular_tools.runners.stages import without_rosrun


def test_a_tool_runs_from_the_path_rosrun_would_find():
    command = without_rosrun(["rosrun", "granular_ros", "classify_registration", "--help"])
    assert command[0] != "rosrun" and command[0].endswith("/granular_ros/classify_registration")
    assert command[1:] == ["--help"]
    direct = subprocess.run(command, capture_output=True, text=True, check=True)
    through_rosrun = subprocess.run(["rosrun", "granular_ros", "classify_registration", "--help"],
                                    capture_output=True, text=True, check=True)
    assert direct.stdout == through_rosrun.stdout and "usage: classify_registration" in direct.stdout


def test_a_python_tool_is_the_one_catkin_installed_for_the_system_interpreter():
    path = without_rosrun(["rosrun", "granular_tools", "simulate_drive"])[0]
    assert "/scripts/" not in path  # not the source script
    with open(path, encoding="utf-8") as script:
        assert script.readline().startswith("#!/usr/bin/python3")


def test_what_catkin_does_not_know_is_left_to_rosrun():
    unknown = ["rosrun", "granular_ros", "no_such_tool", "--x"]
    assert without_rosrun(unknown) == unknown
    assert without_rosrun(["rosrun", "no_such_package", "tool"]) == ["rosrun", "no_such_package",
                                                                     "tool"]
    assert without_rosrun(["ls", "-l"]) == ["ls", "-l"]
    assert without_rosrun(["rosrun"]) == ["rosrun"]
