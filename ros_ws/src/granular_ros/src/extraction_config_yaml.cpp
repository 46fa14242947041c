#include "granular_ros/extraction_config_yaml.h"

#include <stdexcept>
#include <string>

#include <yaml-cpp/yaml.h>

namespace granular_ros {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& key,
                       const std::string& what) {
  throw std::runtime_error(file.string() + ": " + key + ": " + what);
}

YAML::Node sequence(const std::filesystem::path& file, const std::string& key,
                    const YAML::Node& node) {
  if (!node.IsSequence()) {
    fail(file, key, "expected a list, e.g. [1, 2]");
  }
  return node;
}

template <typename T>
T scalar(const std::filesystem::path& file, const std::string& key, const YAML::Node& node,
         const std::string& expected) {
  if (!node.IsScalar()) {
    fail(file, key, "expected " + expected);
  }
  try {
    return node.as<T>();
  } catch (const YAML::BadConversion&) {
    fail(file, key, "expected " + expected + ", got '" + node.Scalar() + "'");
  }
}

}  // namespace

void loadExtractionConfig(const std::filesystem::path& file, granular::ExtractionConfig& config) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(file.string() + ": cannot open for reading");
  } catch (const YAML::ParserException& error) {
    throw std::runtime_error(file.string() + ": not valid YAML: " + error.what());
  }
  if (root.IsNull()) {
    return;
  }
  if (!root.IsMap()) {
    throw std::runtime_error(file.string() + ": expected a mapping of keys to values");
  }

  for (const auto& entry : root) {
    if (!entry.first.IsScalar()) {
      throw std::runtime_error(file.string() + ": keys must be plain names");
    }
    const std::string key = entry.first.Scalar();
    const YAML::Node& value = entry.second;
    if (key == "padding") {
      const YAML::Node values = sequence(file, key, value);
      if (values.size() != 3) {
        fail(file, key, "expected three values [x, y, z] in metres");
      }
      for (std::size_t axis = 0; axis < 3; ++axis) {
        config.padding[static_cast<Eigen::Index>(axis)] =
            scalar<double>(file, key + "[" + std::to_string(axis) + "]", values[axis], "a number");
      }
    } else if (key == "n_thresh") {
      config.n_thresh.clear();
      for (std::size_t i = 0; i < sequence(file, key, value).size(); ++i) {
        const std::string item = key + "[" + std::to_string(i) + "]";
        const long long threshold = scalar<long long>(file, item, value[i], "an integer");
        if (threshold < 1) {
          fail(file, item, "must be at least 1, got " + std::to_string(threshold));
        }
        config.n_thresh.push_back(static_cast<std::size_t>(threshold));
      }
    } else if (key == "labels") {
      config.labels.clear();
      for (std::size_t i = 0; i < sequence(file, key, value).size(); ++i) {
        config.labels.push_back(
            scalar<std::string>(file, key + "[" + std::to_string(i) + "]", value[i], "a label"));
      }
    } else {
      fail(file, key, "unknown key (known: padding, n_thresh, labels)");
    }
  }
}

}  // namespace granular_ros
