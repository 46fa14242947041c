#include "granular_ros/classification_config_yaml.h"

#include <string>

#include "granular_ros/yaml_reader.h"

namespace granular_ros {
namespace {

YamlReader::Handlers icpHandlers(const YamlReader& reader, granular::IcpClassifierConfig& icp) {
  return {{"max_iterations", reader.set(icp.max_iterations)},
          {"max_correspondence_distance", reader.set(icp.max_correspondence_distance)},
          {"transformation_epsilon", reader.set(icp.transformation_epsilon)},
          {"euclidean_fitness_epsilon", reader.set(icp.euclidean_fitness_epsilon)}};
}

void loadPreset(const YamlReader& reader, const std::string& path, const YAML::Node& node,
                granular::RegistrationClassifierConfig& config) {
  granular::NdtClassifierConfig& ndt = config.ndt;
  reader.forEachKey(
      path, node,
      {{"icp",
        [&](const std::string& key, const YAML::Node& value) {
          reader.forEachKey(key, value, icpHandlers(reader, config.icp));
        }},
       {"icp_nl",
        [&](const std::string& key, const YAML::Node& value) {
          reader.forEachKey(key, value, icpHandlers(reader, config.icp_nl));
        }},
       {"ndt",
        [&](const std::string& key, const YAML::Node& value) {
          reader.forEachKey(key, value,
                            {{"transformation_epsilon", reader.set(ndt.transformation_epsilon)},
                             {"step_size", reader.set(ndt.step_size)},
                             {"max_iterations", reader.set(ndt.max_iterations)},
                             {"resolution", reader.set(ndt.resolution)},
                             {"min_points_per_voxel", reader.set(ndt.min_points_per_voxel)},
                             {"outlier_ratio", reader.set(ndt.outlier_ratio)}});
        }},
       {"source_min_z", [&](const std::string& key, const YAML::Node& value) {
          if (value.IsNull()) {
            config.source_min_z.reset();
          } else {
            config.source_min_z = reader.number(key, value);
          }
        }}});
}

}  // namespace

void loadRegistrationPresets(
    const std::filesystem::path& file,
    std::map<std::string, granular::RegistrationClassifierConfig>& presets) {
  const YamlReader reader(file);
  reader.forEachKey("", reader.load(), {{"presets", [&](const std::string& path,
                                                        const YAML::Node& node) {
    if (!node.IsNull() && !node.IsMap()) {
      reader.fail(path, "expected a mapping of preset names to parameters");
    }
    for (const auto& entry : node) {
      const std::string name = reader.text(path, entry.first);
      // operator[] starts a new preset from the defaults.
      loadPreset(reader, path + "." + name, entry.second, presets[name]);
    }
  }}});
}

}  // namespace granular_ros
