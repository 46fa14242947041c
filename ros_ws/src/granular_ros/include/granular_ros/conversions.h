#pragma once

#include <vector>

#include <granular_core/dataset/detections.h>
#include <granular_core/geometry/oriented_box.h>
#include <granular_core/point_types.h>
#include <lgsvl_msgs/Detection3DArray.h>
#include <sensor_msgs/PointCloud2.h>

namespace granular_ros {

/// The cloud's points. x, y and z must be float32 fields (std::runtime_error otherwise);
/// intensity and timestamp are read from any numeric type, and are 0 when absent.
granular::Cloud toCloud(const sensor_msgs::PointCloud2& message);

/// The detections of a message as extraction reads them (id, label, box).
std::vector<granular::Detection> toDetections(const lgsvl_msgs::Detection3DArray& message);

/// A Detection3D of a box (label, id and score as given; no velocity).
lgsvl_msgs::Detection3D toMessage(const granular::OrientedBox& box, const std::string& label,
                                  std::uint32_t id, float score);

}  // namespace granular_ros
