#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include <yaml-cpp/yaml.h>

namespace granular_ros {

/// Reads the values of one YAML config file, naming the file and the key path (e.g.
/// `filters.voxel_grid.leaf_size`) in every error, a std::runtime_error.
class YamlReader {
 public:
  explicit YamlReader(std::filesystem::path file) : file_(std::move(file)) {}

  /// The file's top-level mapping (null for an empty file): an error when the file cannot be
  /// read, is not YAML, or holds something other than a mapping.
  YAML::Node load() const;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  using Handler = std::function<void(const std::string&, const YAML::Node&)>;
  using Handlers = std::map<std::string, Handler>;

  /// Calls the handler of each key of the mapping `node` at `path` with the key's full path;
  /// a key without a handler is an error that lists the known ones. A null node has no keys.
  void forEachKey(const std::string& path, const YAML::Node& node,
                  const Handlers& handlers) const;

  /// `node` as a list (an error otherwise).
  const YAML::Node& sequence(const std::string& key, const YAML::Node& node) const;

  double number(const std::string& key, const YAML::Node& node) const;
  int integer(const std::string& key, const YAML::Node& node) const;
  /// A non-negative integer.
  std::size_t count(const std::string& key, const YAML::Node& node) const;
  /// true or false.
  bool flag(const std::string& key, const YAML::Node& node) const;
  /// Plain text; `expected` says what in an error.
  std::string text(const std::string& key, const YAML::Node& node,
                   const std::string& expected = "a name") const;

  /// Handlers that store a value in `field` (which must outlive them).
  Handler set(double& field) const;
  Handler set(int& field) const;
  Handler set(std::size_t& field) const;

 private:
  template <typename T>
  T scalar(const std::string& key, const YAML::Node& node, const std::string& expected) const;

  std::filesystem::path file_;
};

}  // namespace granular_ros
