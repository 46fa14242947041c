"""rviz helpers: boxes of lgsvl_msgs detections as markers."""
