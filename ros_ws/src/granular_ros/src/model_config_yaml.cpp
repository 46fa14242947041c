#include "granular_ros/model_config_yaml.h"

#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace granular_ros {
namespace {

using granular::FilterStage;

// Reads the values of one YAML file, naming the file and the key path in every error.
class Reader {
 public:
  explicit Reader(std::filesystem::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::runtime_error(file_.string() + ": " + key + ": " + what);
  }

  using Handler = std::function<void(const std::string&, const YAML::Node&)>;
  using Handlers = std::map<std::string, Handler>;

  // Calls the handler of each key of the mapping `node` at `path` with the key's full path.
  void forEachKey(const std::string& path, const YAML::Node& node,
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

  double number(const std::string& key, const YAML::Node& node) const {
    return scalar<double>(key, node, "a number");
  }

  int integer(const std::string& key, const YAML::Node& node) const {
    const long long value = scalar<long long>(key, node, "an integer");
    if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
      fail(key, "integer out of range");
    }
    return static_cast<int>(value);
  }

  std::size_t count(const std::string& key, const YAML::Node& node) const {
    const long long value = scalar<long long>(key, node, "an integer");
    if (value < 0) {
      fail(key, "must not be negative, got " + std::to_string(value));
    }
    return static_cast<std::size_t>(value);
  }

  std::string text(const std::string& key, const YAML::Node& node) const {
    return scalar<std::string>(key, node, "a name");
  }

  std::vector<FilterStage> stages(const std::string& key, const YAML::Node& node) const {
    if (!node.IsSequence()) {
      fail(key, "expected a list of stages, e.g. [pass_through, voxel_grid]");
    }
    std::vector<FilterStage> order;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string item = key + "[" + std::to_string(i) + "]";
      const std::string name = text(item, node[i]);
      const auto stage = granular::stageFromName(name);
      if (!stage) {
        fail(item, "unknown stage '" + name +
                       "' (known: pass_through, radius_outlier, statistical_outlier, voxel_grid)");
      }
      order.push_back(*stage);
    }
    return order;
  }

 private:
  template <typename T>
  T scalar(const std::string& key, const YAML::Node& node, const std::string& expected) const {
    if (!node.IsScalar()) {
      fail(key, "expected " + expected);
    }
    try {
      return node.as<T>();
    } catch (const YAML::BadConversion&) {
      fail(key, "expected " + expected + ", got '" + node.Scalar() + "'");
    }
  }

  std::filesystem::path file_;
};

// The chain's keys; the same layout serves the shared chain and the class overrides.
template <typename Set>
Reader::Handlers chainHandlers(const Reader& reader, Set set) {
  return {
      {"order", [&reader, set](const std::string& key,
                               const YAML::Node& node) { set.order(reader.stages(key, node)); }},
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

  const Reader reader(file);
  granular::IcpConfig& icp = config.icp;
  granular::MeshConfig& mesh = config.mesh;
  const auto number = [&reader](double& field) {
    return [&reader, &field](const std::string& key, const YAML::Node& node) {
      field = reader.number(key, node);
    };
  };
  const auto integer = [&reader](int& field) {
    return [&reader, &field](const std::string& key, const YAML::Node& node) {
      field = reader.integer(key, node);
    };
  };
  const auto count = [&reader](std::size_t& field) {
    return [&reader, &field](const std::string& key, const YAML::Node& node) {
      field = reader.count(key, node);
    };
  };

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
