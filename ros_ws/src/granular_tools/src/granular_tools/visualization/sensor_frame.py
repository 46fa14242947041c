"""The sensor's frame made known to tf, for rviz.

rviz's fixed frame is the sensor's (`velodyne` in config/*.rviz). With no tf data at all rviz
shows "Global Status: Warn" (Fixed Frame [velodyne] does not exist), although every message is
in that frame and is drawn. One static identity transform from the sensor's frame to a child
`<frame>_view` makes the frame exist without giving it a parent, so a bag's own tf still places
the sensor wherever it says."""
from geometry_msgs.msg import TransformStamped


def view_transform(frame, stamp):
    """The identity from `frame` (the parent) to its child `<frame>_view`."""
    transform = TransformStamped()
    transform.header.stamp = stamp
    transform.header.frame_id = frame
    transform.child_frame_id = f"{frame}_view"
    transform.transform.rotation.w = 1.0
    return transform
