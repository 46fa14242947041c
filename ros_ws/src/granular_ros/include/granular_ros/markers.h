#pragma once

#include <string>
#include <vector>

#include <lgsvl_msgs/Detection3DArray.h>
#include <visualization_msgs/MarkerArray.h>

namespace granular_ros {

/// rviz markers of classified detections: each box as an outline in its predicted class's
/// colour (the palette of granular_tools' detection_markers) and a tag above it with the
/// predicted label and score. Where the true label is known (`truth[i]` not empty) the tag
/// says whether the prediction is right; a wrong one gets a red tag "X Predicted (true: Label)"
/// and a thicker outline. Objects labelled "unknown" (too few points to classify) get a small
/// grey tag. With `tracks` (the detections are segment_cloud's tracks), each tag starts with
/// the detection's id ("#12 Sedan 0.83") and an arrow from the box's top centre shows its
/// velocity (x-y, in the boxes' frame), as long as the distance it covers in a second.
/// DELETEALL first, so that boxes of the previous frame go.
visualization_msgs::MarkerArray predictionMarkers(const lgsvl_msgs::Detection3DArray& predicted,
                                                  const std::vector<std::string>& truth,
                                                  double lifetime, bool tracks = false);

}  // namespace granular_ros
