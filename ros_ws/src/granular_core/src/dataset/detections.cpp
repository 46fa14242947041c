#include "granular_core/dataset/detections.h"

#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace granular {
namespace {

using nlohmann::json;
// Written with the keys in the message's order, as bag to files writes them.
using Ordered = nlohmann::ordered_json;

// Walks a JSON document, keeping the key path for error messages.
class Reader {
 public:
  explicit Reader(const std::filesystem::path& file) : file_(file) {}

  const json& child(const json& node, const std::string& path, const std::string& key) const {
    if (!node.is_object()) {
      fail(path, "expected an object, got " + std::string(node.type_name()));
    }
    const auto it = node.find(key);
    if (it == node.end()) {
      fail(join(path, key), "missing key");
    }
    return *it;
  }

  double number(const json& node, const std::string& path, const std::string& key) const {
    const json& value = child(node, path, key);
    if (!value.is_number()) {
      fail(join(path, key), "expected a number, got " + std::string(value.type_name()));
    }
    return value.get<double>();
  }

  Eigen::Vector3d vector3(const json& node, const std::string& path, const std::string& key) const {
    const json& value = child(node, path, key);
    const std::string value_path = join(path, key);
    return {number(value, value_path, "x"), number(value, value_path, "y"),
            number(value, value_path, "z")};
  }

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw std::runtime_error(file_.string() + ": " + (path.empty() ? "top level" : path) + ": " +
                             what);
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  std::filesystem::path file_;
};

}  // namespace

std::vector<Detection> readDetectionsJson(const std::filesystem::path& file,
                                          DetectionsHeader* header) {
  std::ifstream stream(file);
  if (!stream) {
    throw std::runtime_error(file.string() + ": cannot open for reading");
  }
  json document;
  try {
    document = json::parse(stream);
  } catch (const json::parse_error& error) {
    throw std::runtime_error(file.string() + ": not valid JSON: " + error.what());
  }

  const Reader reader(file);
  if (header != nullptr && document.is_object() && document.contains("header") &&
      document["header"].is_object()) {
    // Each part when present: the header is not needed to read the detections.
    const json& node = document["header"];
    if (node.contains("stamp")) {
      const json& stamp = node["stamp"];
      header->secs = static_cast<std::int64_t>(reader.number(stamp, "header.stamp", "secs"));
      header->nsecs = static_cast<std::int64_t>(reader.number(stamp, "header.stamp", "nsecs"));
    }
    if (node.contains("frame_id")) {
      const json& frame_id = node["frame_id"];
      if (!frame_id.is_string()) {
        reader.fail("header.frame_id",
                    "expected a string, got " + std::string(frame_id.type_name()));
      }
      header->frame_id = frame_id.get<std::string>();
    }
  }
  const json& detections = reader.child(document, "", "detections");
  if (!detections.is_array()) {
    reader.fail("detections", "expected an array, got " + std::string(detections.type_name()));
  }

  std::vector<Detection> result;
  result.reserve(detections.size());
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const json& node = detections[i];
    const std::string path = "detections[" + std::to_string(i) + "]";
    Detection detection;

    const json& id = reader.child(node, path, "id");
    if (!id.is_number_integer()) {
      reader.fail(path + ".id", "expected an integer, got " + std::string(id.type_name()));
    }
    detection.id = id.get<std::int64_t>();

    const json& label = reader.child(node, path, "label");
    if (!label.is_string()) {
      reader.fail(path + ".label", "expected a string, got " + std::string(label.type_name()));
    }
    detection.label = label.get<std::string>();

    const std::string bbox_path = path + ".bbox";
    const json& bbox = reader.child(node, path, "bbox");
    const std::string pose_path = bbox_path + ".position";
    const json& pose = reader.child(bbox, bbox_path, "position");
    detection.centre = reader.vector3(pose, pose_path, "position");
    const std::string orientation_path = pose_path + ".orientation";
    const json& orientation = reader.child(pose, pose_path, "orientation");
    detection.orientation = Eigen::Quaterniond(reader.number(orientation, orientation_path, "w"),
                                               reader.number(orientation, orientation_path, "x"),
                                               reader.number(orientation, orientation_path, "y"),
                                               reader.number(orientation, orientation_path, "z"));
    detection.size = reader.vector3(bbox, bbox_path, "size");
    if (node.contains("score")) {
      detection.score = reader.number(node, path, "score");
    }
    if (node.contains("velocity")) {
      const json& velocity = reader.child(node, path, "velocity");
      detection.velocity = reader.vector3(velocity, path + ".velocity", "linear");
    }
    if (node.contains("header") && node["header"].is_object() &&
        node["header"].contains("frame_id") && node["header"]["frame_id"].is_string()) {
      detection.frame_id = node["header"]["frame_id"].get<std::string>();
    }
    result.push_back(std::move(detection));
  }
  return result;
}

std::string detectionsJson(const std::vector<Detection>& detections,
                           const DetectionsHeader& header) {
  const auto xyz = [](double x, double y, double z) {
    Ordered vector = Ordered::object();
    vector["x"] = x;
    vector["y"] = y;
    vector["z"] = z;
    return vector;
  };
  Ordered header_json = Ordered::object();
  header_json["stamp"] = {{"secs", header.secs}, {"nsecs", header.nsecs}};
  header_json["frame_id"] = header.frame_id;
  header_json["seq"] = 0;
  Ordered array = Ordered::array();
  for (const Detection& detection : detections) {
    Ordered orientation =
        xyz(detection.orientation.x(), detection.orientation.y(), detection.orientation.z());
    orientation["w"] = detection.orientation.w();
    Ordered pose = Ordered::object();
    pose["position"] = xyz(detection.centre.x(), detection.centre.y(), detection.centre.z());
    pose["orientation"] = orientation;
    Ordered bbox = Ordered::object();
    bbox["position"] = pose;
    bbox["size"] = xyz(detection.size.x(), detection.size.y(), detection.size.z());
    Ordered entry = Ordered::object();
    entry["header"] = header_json;
    entry["id"] = detection.id;
    entry["label"] = detection.label;
    entry["score"] = detection.score;
    entry["bbox"] = bbox;
    const Eigen::Vector3d& velocity = detection.velocity;
    entry["velocity"] = {{"linear", xyz(velocity.x(), velocity.y(), velocity.z())},
                         {"angular", xyz(0, 0, 0)}};
    array.push_back(entry);
  }
  Ordered document = Ordered::object();
  document["header"] = header_json;
  document["detections"] = array;
  return document.dump() + "\n";
}

}  // namespace granular
