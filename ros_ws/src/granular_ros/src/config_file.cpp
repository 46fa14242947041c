#include "granular_ros/config_file.h"

#include <string>

#include <yaml-cpp/yaml.h>

namespace granular_ros {
namespace {

granular::config::Json toJson(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      granular::config::Json json = granular::config::Json::object();
      for (const auto& entry : node) {
        json[entry.first.Scalar()] = toJson(entry.second);
      }
      return json;
    }
    case YAML::NodeType::Sequence: {
      granular::config::Json json = granular::config::Json::array();
      for (const auto& item : node) {
        json.push_back(toJson(item));
      }
      return json;
    }
    case YAML::NodeType::Scalar:
      return node.Scalar();
    default:
      return nullptr;
  }
}

// A key must be plain text; a list or mapping as a key is an error naming where it is.
void checkKeys(const YAML::Node& node, const std::filesystem::path& file,
               const std::string& path) {
  if (node.IsMap()) {
    for (const auto& entry : node) {
      if (!entry.first.IsScalar()) {
        throw std::runtime_error(file.string() + ": " + (path.empty() ? "" : path + ": ") +
                                 "keys must be plain names");
      }
      checkKeys(entry.second, file,
                path.empty() ? entry.first.Scalar() : path + "." + entry.first.Scalar());
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      checkKeys(node[i], file, path + "[" + std::to_string(i) + "]");
    }
  }
}

}  // namespace

granular::config::Json readYamlFile(const std::filesystem::path& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(file.string() + ": cannot open for reading");
  } catch (const YAML::ParserException& error) {
    throw std::runtime_error(file.string() + ": not valid YAML: " + error.what());
  }
  if (!root.IsNull() && !root.IsMap()) {
    throw std::runtime_error(file.string() + ": expected a mapping of keys to values");
  }
  checkKeys(root, file, "");
  return toJson(root);
}

}  // namespace granular_ros
