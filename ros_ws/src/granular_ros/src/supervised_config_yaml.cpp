#include "granular_ros/supervised_config_yaml.h"

#include <string>

#include "granular_ros/yaml_reader.h"

namespace granular_ros {

void loadSupervisedConfig(const std::filesystem::path& file, granular::SupervisedConfig& config) {
  const YamlReader reader(file);
  granular::SvmConfig& svm = config.svm;
  granular::PointHistogramConfig& histograms = config.histograms;
  reader.forEachKey(
      "", reader.load(),
      {{"knn",
        [&](const std::string& path, const YAML::Node& node) {
          reader.forEachKey(path, node,
                            {{"k", reader.set(config.knn.k)},
                             {"standardize", [&](const std::string& key, const YAML::Node& value) {
                                config.knn.standardize = reader.flag(key, value);
                              }}});
        }},
       {"svm",
        [&](const std::string& path, const YAML::Node& node) {
          reader.forEachKey(
              path, node,
              {{"nu",
                [&](const std::string& key, const YAML::Node& value) {
                  svm.nu.clear();
                  for (std::size_t i = 0; i < reader.sequence(key, value).size(); ++i) {
                    svm.nu.push_back(reader.number(key + "[" + std::to_string(i) + "]", value[i]));
                  }
                }},
               {"log2_gamma_min", reader.set(svm.log2_gamma_min)},
               {"log2_gamma_max", reader.set(svm.log2_gamma_max)},
               {"log2_gamma_step", reader.set(svm.log2_gamma_step)},
               {"refinements", reader.set(svm.refinements)},
               {"folds", reader.set(svm.folds)},
               {"seed", [&](const std::string& key, const YAML::Node& value) {
                  svm.seed = static_cast<std::uint32_t>(reader.count(key, value));
                }}});
        }},
       {"histograms", [&](const std::string& path, const YAML::Node& node) {
          reader.forEachKey(
              path, node,
              {{"sample_points", reader.set(histograms.sample_points)},
               {"neighbours", reader.set(histograms.neighbours)},
               {"neighbour_radius", reader.set(histograms.neighbour_radius)},
               {"bins", reader.set(histograms.bins)},
               {"cylinder_height", reader.set(histograms.cylinder_height)},
               {"cylinder_radius", reader.set(histograms.cylinder_radius)},
               {"cylinder_slices", reader.set(histograms.cylinder_slices)},
               {"scatter",
                [&](const std::string& key, const YAML::Node& value) {
                  const std::string name = reader.text(key, value);
                  const auto scatter = granular::scatterDefinitionFromName(name);
                  if (!scatter) {
                    reader.fail(key, "expected smallest or largest, got '" + name + "'");
                  }
                  histograms.scatter = *scatter;
                }},
               {"seed", [&](const std::string& key, const YAML::Node& value) {
                  histograms.seed = static_cast<std::uint32_t>(reader.count(key, value));
                }}});
        }}});
}

}  // namespace granular_ros
