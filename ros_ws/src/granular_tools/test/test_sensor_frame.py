"""sensor_frame: rviz's fixed frame made known to tf, by every launch file that opens rviz."""
import xml.etree.ElementTree as ElementTree

import rospy

from conftest import REPO_ROOT
from granular_tools.visualization.sensor_frame import view_transform


def test_the_sensor_frame_is_the_parent_so_a_bags_own_tf_still_places_it():
    transform = view_transform("velodyne", rospy.Time(12, 5))
    assert transform.header.frame_id == "velodyne"
    assert transform.child_frame_id == "velodyne_view"
    assert transform.header.stamp == rospy.Time(12, 5)
    translation, rotation = transform.transform.translation, transform.transform.rotation
    assert (translation.x, translation.y, translation.z) == (0.0, 0.0, 0.0)
    assert (rotation.x, rotation.y, rotation.z, rotation.w) == (0.0, 0.0, 0.0, 1.0)


def test_every_launch_file_that_opens_rviz_announces_its_fixed_frame():
    opening = []
    for launch in sorted((REPO_ROOT / "launch").glob("*.launch")):
        nodes = list(ElementTree.parse(launch).iter("node"))
        rviz = [node for node in nodes if node.get("pkg") == "rviz"]
        if not rviz:
            continue
        opening.append(launch.name)
        frames = [node for node in nodes if node.get("type") == "sensor_frame"]
        # Started with rviz, under the same condition.
        assert [node.get("if") for node in frames] == [rviz[0].get("if")], launch.name
    assert len(opening) == 4, opening
