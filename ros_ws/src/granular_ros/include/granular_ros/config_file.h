#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include <granular_core/config/fields.h>

namespace granular_ros {

/// A YAML config file as JSON for granular::config::readJson: mappings, lists, null for YAML's
/// null, every other value as its text (YAML has no types the reader could trust; the reader
/// parses each value as its field wants it). Throws std::runtime_error naming the file when it
/// cannot be read, is not YAML, or holds something other than a mapping.
granular::config::Json readYamlFile(const std::filesystem::path& file);

/// Lays the keys of the YAML file `file` over `config` through the config's field list,
/// strictly: an unknown key, a value of the wrong type or shape is a std::runtime_error naming
/// the file, the dotted key (e.g. `filters.voxel_grid.leaf_size`) and, for an unknown key, the
/// known ones. Keys left out keep their values. Ranges are checked by the config's validate().
template <typename Config>
void loadConfigFile(const std::filesystem::path& file, Config& config) {
  const granular::config::Json json = readYamlFile(file);
  try {
    granular::config::readJson(json, config);
  } catch (const granular::config::FieldError& error) {
    throw std::runtime_error(file.string() + ": " + error.what());
  }
}

/// A tool's configuration: the defaults, then the YAML file `file` when given, then `adjust`
/// (the command-line options), then the config's validate(); a value out of range is a
/// std::invalid_argument "invalid configuration: ...".
template <typename Config>
Config buildConfig(const std::optional<std::string>& file,
                   const std::function<void(Config&)>& adjust = {}) {
  Config config;
  if (file) {
    loadConfigFile(*file, config);
  }
  if (adjust) {
    adjust(config);
  }
  try {
    validate(config);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("invalid configuration: ") + error.what());
  }
  return config;
}

/// For --help: every key of a config file with its default and unit, one per line, indented.
/// The value of a config enum E named `name` on the command line; otherwise an error naming
/// `option` and the choices.
template <typename E>
E parseChoice(const std::string& option, const std::string& name) {
  const std::optional<E> value = granular::config::enumFromName<E>(name);
  if (!value) {
    throw std::invalid_argument(option + ": expected " + granular::config::enumChoices<E>() +
                                ", got '" + name + "'");
  }
  return *value;
}

template <typename Config>
std::string configurationHelp(const Config& defaults = Config()) {
  std::string text;
  for (const std::string& line : granular::config::describeFields(defaults)) {
    text += "  " + line + "\n";
  }
  return text;
}

}  // namespace granular_ros
