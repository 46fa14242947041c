#include "granular_ros/yaml_reader.h"

#include <limits>
#include <stdexcept>

namespace granular_ros {

YAML::Node YamlReader::load() const {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file_.string());
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(file_.string() + ": cannot open for reading");
  } catch (const YAML::ParserException& error) {
    throw std::runtime_error(file_.string() + ": not valid YAML: " + error.what());
  }
  if (!root.IsNull() && !root.IsMap()) {
    throw std::runtime_error(file_.string() + ": expected a mapping of keys to values");
  }
  return root;
}

void YamlReader::fail(const std::string& key, const std::string& what) const {
  throw std::runtime_error(file_.string() + ": " + key + ": " + what);
}

void YamlReader::forEachKey(const std::string& path, const YAML::Node& node,
                            const Handlers& handlers) const {
  if (node.IsNull()) {
    return;
  }
  if (!node.IsMap()) {
    fail(path, "expected a mapping of keys to values");
  }
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) {
      fail(path, "keys must be plain names");
    }
    const std::string key = entry.first.Scalar();
    const std::string key_path = path.empty() ? key : path + "." + key;
    const auto handler = handlers.find(key);
    if (handler == handlers.end()) {
      std::string known;
      for (const auto& [name, unused] : handlers) {
        known += (known.empty() ? "" : ", ") + name;
      }
      fail(key_path, "unknown key (known: " + known + ")");
    }
    handler->second(key_path, entry.second);
  }
}

const YAML::Node& YamlReader::sequence(const std::string& key, const YAML::Node& node) const {
  if (!node.IsSequence()) {
    fail(key, "expected a list, e.g. [1, 2]");
  }
  return node;
}

double YamlReader::number(const std::string& key, const YAML::Node& node) const {
  return scalar<double>(key, node, "a number");
}

int YamlReader::integer(const std::string& key, const YAML::Node& node) const {
  const long long value = scalar<long long>(key, node, "an integer");
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    fail(key, "integer out of range");
  }
  return static_cast<int>(value);
}

std::size_t YamlReader::count(const std::string& key, const YAML::Node& node) const {
  const long long value = scalar<long long>(key, node, "an integer");
  if (value < 0) {
    fail(key, "must not be negative, got " + std::to_string(value));
  }
  return static_cast<std::size_t>(value);
}

bool YamlReader::flag(const std::string& key, const YAML::Node& node) const {
  return scalar<bool>(key, node, "true or false");
}

std::string YamlReader::text(const std::string& key, const YAML::Node& node,
                             const std::string& expected) const {
  return scalar<std::string>(key, node, expected);
}

YamlReader::Handler YamlReader::set(double& field) const {
  return [this, &field](const std::string& key, const YAML::Node& node) {
    field = number(key, node);
  };
}

YamlReader::Handler YamlReader::set(int& field) const {
  return [this, &field](const std::string& key, const YAML::Node& node) {
    field = integer(key, node);
  };
}

YamlReader::Handler YamlReader::set(std::size_t& field) const {
  return [this, &field](const std::string& key, const YAML::Node& node) {
    field = count(key, node);
  };
}

template <typename T>
T YamlReader::scalar(const std::string& key, const YAML::Node& node,
                     const std::string& expected) const {
  if (!node.IsScalar()) {
    fail(key, "expected " + expected);
  }
  try {
    return node.as<T>();
  } catch (const YAML::BadConversion&) {
    fail(key, "expected " + expected + ", got '" + node.Scalar() + "'");
  }
}

}  // namespace granular_ros
