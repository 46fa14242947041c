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
  /// The detector's confidence; 1 when the file has none (ground truth).
  double score = 1.0;
  /// Linear velocity in the LiDAR frame, m/s (a tracker's estimate; 0 when not known).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// The detection's own header.frame_id; empty when the file gives none (the array's, the
  /// cloud's frame, applies).
  std::string frame_id;
};

/// The header of a Detection3DArray: the frame's stamp and the sensor frame's id.
struct DetectionsHeader {
  std::int64_t secs = 0;
  std::int64_t nsecs = 0;
  std::string frame_id;
};

/// Reads `detections[]` of a lgsvl_msgs/Detection3DArray written as JSON by the bag-to-files
/// tool (id, label, bbox.position.position, bbox.position.orientation, bbox.size per detection;
/// `score`, `velocity.linear` and the detection's header.frame_id when present; other keys
/// are ignored). Throws std::runtime_error whose message names the file and, for a missing key
/// or a value of the wrong type, the key's path (e.g. `detections[2].bbox.size.x`). `header`,
/// when given, receives the array's header (stamp and frame id, each left as it is where the
/// file has none).
std::vector<Detection> readDetectionsJson(const std::filesystem::path& file,
                                          DetectionsHeader* header = nullptr);

/// `detections` as a lgsvl_msgs/Detection3DArray in the JSON layout bag to files writes (every
/// field of the message: each detection gets the array's header, its linear velocity and a
/// zero angular one), so that
/// every tool that reads a frames folder's detections_3d/ reads it. Numbers are written so that
/// they read back to the same double.
std::string detectionsJson(const std::vector<Detection>& detections,
                           const DetectionsHeader& header);

}  // namespace granular
