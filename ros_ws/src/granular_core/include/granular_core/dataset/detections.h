#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace granular {

/// One 3-D detection as read from a detections JSON file, before validation: the box fields are
/// kept exactly as written (OrientedBox validates and normalises them).
struct Detection {
  std::int64_t id = 0;
  std::string label;
  /// Box centre in the LiDAR frame, metres.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  /// Box orientation, sensor frame <- box axes; not necessarily unit.
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  /// (length, width, height), metres.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
};

/// Reads `detections[]` of a lgsvl_msgs/Detection3DArray written as JSON by the bag-to-files
/// tool (id, label, bbox.position.position, bbox.position.orientation, bbox.size per detection;
/// other keys are ignored). Throws std::runtime_error whose message names the file and, for a
/// missing key or a value of the wrong type, the key's path (e.g. `detections[2].bbox.size.x`).
std::vector<Detection> readDetectionsJson(const std::filesystem::path& file);

}  // namespace granular
