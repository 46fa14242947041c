// Detections JSON in the layout bag to files writes, for tests that build frames by hand.
#pragma once

#include <string>

namespace granular {
namespace testing_support {

// One lgsvl_msgs/Detection3D with an unrotated box; position and size are JSON objects.
inline std::string detectionJson(int id, const std::string& label, const std::string& position,
                                 const std::string& size) {
  return R"({"header": {"stamp": {"secs": 0, "nsecs": 0}, "frame_id": "", "seq": 0}, "id": )" +
         std::to_string(id) + R"(, "label": ")" + label +
         R"(", "score": 1.0, "bbox": {"position": {"position": )" + position +
         R"(, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}, "size": )" + size +
         R"(}, "velocity": {"linear": {"x": 0, "y": 0, "z": 0},)"
         R"( "angular": {"x": 0, "y": 0, "z": 0}}})";
}

// One lgsvl_msgs/Detection3DArray around a comma-separated list of detections.
inline std::string frameJson(const std::string& detections) {
  return R"({"header": {"stamp": {"secs": 1586102742, "nsecs": 765440}, "frame_id": "velodyne",)"
         R"( "seq": 375}, "detections": [)" +
         detections + "]}";
}

}  // namespace testing_support
}  // namespace granular
