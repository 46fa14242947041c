#include "granular_ros/extraction_config_yaml.h"

#include <string>

#include "granular_ros/yaml_reader.h"

namespace granular_ros {

void loadExtractionConfig(const std::filesystem::path& file, granular::ExtractionConfig& config) {
  const YamlReader reader(file);
  reader.forEachKey(
      "", reader.load(),
      {{"padding",
        [&](const std::string& key, const YAML::Node& value) {
          if (reader.sequence(key, value).size() != 3) {
            reader.fail(key, "expected three values [x, y, z] in metres");
          }
          for (std::size_t axis = 0; axis < 3; ++axis) {
            config.padding[static_cast<Eigen::Index>(axis)] =
                reader.number(key + "[" + std::to_string(axis) + "]", value[axis]);
          }
        }},
       {"n_thresh",
        [&](const std::string& key, const YAML::Node& value) {
          config.n_thresh.clear();
          for (std::size_t i = 0; i < reader.sequence(key, value).size(); ++i) {
            const std::string item = key + "[" + std::to_string(i) + "]";
            const int threshold = reader.integer(item, value[i]);
            if (threshold < 1) {
              reader.fail(item, "must be at least 1, got " + std::to_string(threshold));
            }
            config.n_thresh.push_back(static_cast<std::size_t>(threshold));
          }
        }},
       {"labels",
        [&](const std::string& key, const YAML::Node& value) {
          config.labels.clear();
          for (std::size_t i = 0; i < reader.sequence(key, value).size(); ++i) {
            config.labels.push_back(
                reader.text(key + "[" + std::to_string(i) + "]", value[i], "a label"));
          }
        }},
       {"max_box_size", [&](const std::string& key, const YAML::Node& value) {
          config.max_box_size = reader.number(key, value);
        }}});
}

}  // namespace granular_ros
