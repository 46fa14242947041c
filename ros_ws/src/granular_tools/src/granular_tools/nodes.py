"""How every granular rospy node starts."""
import sys

import rosgraph
import rospy


def missing_master(start_with):
    """None while a ROS master answers; otherwise what to tell the user, `start_with` saying
    how else to start the node ("use launch/x.launch, which starts one"). rospy alone would
    retry its registration for ever, deaf to Ctrl-C, or, given a private parameter, end in a
    ConnectionRefusedError traceback."""
    if rosgraph.is_master_online():
        return None
    return f"no ROS master at {rosgraph.get_master_uri()}: start roscore, or {start_with}"


def init_node(name, description):
    """rospy.init_node(name), with what a user who runs the node by hand expects: -h or --help
    prints `description` (the script's docstring) and exits 0, and without a ROS master the
    node says so and exits 1 (a launch file starts the master before its nodes)."""
    if any(argument in ("-h", "--help") for argument in rospy.myargv(sys.argv)[1:]):
        print(description.strip())
        sys.exit(0)
    problem = missing_master("start the node with its launch file")
    if problem:
        print(f"{name}: {problem}", file=sys.stderr)
        sys.exit(1)
    rospy.init_node(name)
