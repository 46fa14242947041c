"""How every granular rospy node starts."""
import sys

import rosgraph
import rospy


def init_node(name, description):
    """rospy.init_node(name), with what a user who runs the node by hand expects: -h or --help
    prints `description` (the script's docstring) and exits 0, and without a ROS master the
    node says so and exits 1. (rospy would retry its registration for ever, deaf to Ctrl-C,
    or, given a private parameter, end in a ConnectionRefusedError traceback; a launch file
    starts the master before its nodes.)"""
    if any(argument in ("-h", "--help") for argument in rospy.myargv(sys.argv)[1:]):
        print(description.strip())
        sys.exit(0)
    if not rosgraph.is_master_online():
        print(f"{name}: no ROS master at {rosgraph.get_master_uri()}: start roscore, or start "
              "the node with its launch file", file=sys.stderr)
        sys.exit(1)
    rospy.init_node(name)
