#include "granular_ros/model_config_yaml.h"

#include <string>
#include <vector>

#include "granular_ros/yaml_reader.h"

namespace granular_ros {
namespace {

using granular::FilterStage;

// A list of filter stage names.
std::vector<FilterStage> stages(const YamlReader& reader, const std::string& key,
                                const YAML::Node& node) {
  if (!node.IsSequence()) {
    reader.fail(key, "expected a list of stages, e.g. [pass_through, voxel_grid]");
  }
  std::vector<FilterStage> order;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string item = key + "[" + std::to_string(i) + "]";
    const std::string name = reader.text(item, node[i]);
    const auto stage = granular::stageFromName(name);
    if (!stage) {
      reader.fail(item, "unknown stage '" + name +
                            "' (known: pass_through, radius_outlier, statistical_outlier, "
                            "voxel_grid)");
    }
    order.push_back(*stage);
  }
  return order;
}

// The chain's keys; the same layout serves the shared chain and the class overrides.
template <typename Set>
YamlReader::Handlers chainHandlers(const YamlReader& reader, Set set) {
  return {
      {"order", [&reader, set](const std::string& key,
                               const YAML::Node& node) { set.order(stages(reader, key, node)); }},
      {"pass_through",
       [&reader, set](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node,
                           {{"min_z", [&](const std::string& key, const YAML::Node& value) {
                               set.min_z(reader.number(key, value));
                             }},
                            {"max_z", [&](const std::string& key, const YAML::Node& value) {
                               set.max_z(reader.number(key, value));
                             }}});
       }},
      {"radius_outlier",
       [&reader, set](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node,
                           {{"radius", [&](const std::string& key, const YAML::Node& value) {
                               set.radius(reader.number(key, value));
                             }},
                            {"min_neighbors", [&](const std::string& key, const YAML::Node& value) {
                               set.min_neighbors(reader.integer(key, value));
                             }}});
       }},
      {"statistical_outlier",
       [&reader, set](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node,
                           {{"mean_k", [&](const std::string& key, const YAML::Node& value) {
                               set.mean_k(reader.integer(key, value));
                             }},
                            {"stddev_mul", [&](const std::string& key, const YAML::Node& value) {
                               set.stddev_mul(reader.number(key, value));
                             }}});
       }},
      {"voxel_grid",
       [&reader, set](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node,
                           {{"leaf_size", [&](const std::string& key, const YAML::Node& value) {
                               set.leaf_size(reader.number(key, value));
                             }}});
       }},
  };
}

// Setters for the shared chain and for a class override, used by chainHandlers.
struct ChainSetter {
  granular::FilterChainConfig* chain;
  void order(std::vector<FilterStage> value) const { chain->order = std::move(value); }
  void min_z(double value) const { chain->pass_through.min_z = value; }
  void max_z(double value) const { chain->pass_through.max_z = value; }
  void radius(double value) const { chain->radius_outlier.radius = value; }
  void min_neighbors(int value) const { chain->radius_outlier.min_neighbors = value; }
  void mean_k(int value) const { chain->statistical_outlier.mean_k = value; }
  void stddev_mul(double value) const { chain->statistical_outlier.stddev_mul = value; }
  void leaf_size(double value) const { chain->voxel_grid.leaf_size = value; }
};

struct OverrideSetter {
  granular::FilterChainOverride* change;
  void order(std::vector<FilterStage> value) const { change->order = std::move(value); }
  void min_z(double value) const { change->min_z = value; }
  void max_z(double value) const { change->max_z = value; }
  void radius(double value) const { change->radius = value; }
  void min_neighbors(int value) const { change->min_neighbors = value; }
  void mean_k(int value) const { change->mean_k = value; }
  void stddev_mul(double value) const { change->stddev_mul = value; }
  void leaf_size(double value) const { change->leaf_size = value; }
};

}  // namespace

void loadModelConfig(const std::filesystem::path& file, granular::ModelBuildConfig& config) {
  const YamlReader reader(file);
  const YAML::Node root = reader.load();
  granular::IcpConfig& icp = config.icp;
  granular::MeshConfig& mesh = config.mesh;
  const auto number = [&reader](double& field) { return reader.set(field); };
  const auto integer = [&reader](int& field) { return reader.set(field); };
  const auto count = [&reader](std::size_t& field) { return reader.set(field); };

  reader.forEachKey("", root, {
      {"method",
       [&](const std::string& key, const YAML::Node& node) {
         const std::string name = reader.text(key, node);
         const auto method = granular::methodFromName(name);
         if (!method) {
           reader.fail(key, "expected plain or icp, got '" + name + "'");
         }
         config.method = *method;
       }},
      {"seed",
       [&](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node, {{"objects_per_side", count(config.seed.objects_per_side)}});
       }},
      {"icp",
       [&](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(
             path, node,
             {{"max_iterations", integer(icp.max_iterations)},
              {"max_correspondence_distance", number(icp.max_correspondence_distance)},
              {"transformation_epsilon", number(icp.transformation_epsilon)},
              {"euclidean_fitness_epsilon", number(icp.euclidean_fitness_epsilon)},
              {"max_fitness", number(icp.max_fitness)},
              {"max_translation", number(icp.max_translation)},
              {"max_rotation_deg", number(icp.max_rotation_deg)},
              {"min_points", count(icp.min_points)},
              {"target_leaf_size", number(icp.target_leaf_size)}});
       }},
      {"filters",
       [&](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node, chainHandlers(reader, ChainSetter{&config.filters}));
       }},
      {"class_filters",
       [&](const std::string& path, const YAML::Node& node) {
         if (!node.IsNull() && !node.IsMap()) {
           reader.fail(path, "expected a mapping of class names to filter settings");
         }
         for (const auto& entry : node) {
           const std::string label = reader.text(path, entry.first);
           reader.forEachKey(path + "." + label, entry.second,
                             chainHandlers(reader, OverrideSetter{&config.class_filters[label]}));
         }
       }},
      {"mesh",
       [&](const std::string& path, const YAML::Node& node) {
         reader.forEachKey(path, node,
                           {{"normal_k", integer(mesh.normal_k)},
                            {"search_radius", number(mesh.search_radius)},
                            {"mu", number(mesh.mu)},
                            {"max_nearest_neighbors", integer(mesh.max_nearest_neighbors)},
                            {"max_surface_angle_deg", number(mesh.max_surface_angle_deg)},
                            {"min_angle_deg", number(mesh.min_angle_deg)},
                            {"max_angle_deg", number(mesh.max_angle_deg)}});
       }},
  });
}

}  // namespace granular_ros
