"""Python (rospy) tools of the granular pipeline: drive simulation, bag conversion, reports."""
