#include "granular_core/dataset/detections.h"

#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace granular {
namespace {

using nlohmann::json;

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

std::vector<Detection> readDetectionsJson(const std::filesystem::path& file) {
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
    result.push_back(std::move(detection));
  }
  return result;
}

}  // namespace granular
