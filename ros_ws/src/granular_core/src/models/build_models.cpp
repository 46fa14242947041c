#include "granular_core/models/build_models.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <system_error>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/models/concatenate.h"
#include "granular_core/models/icp_concatenate.h"
#include "granular_core/models/mesh.h"

namespace granular {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;


// The absolute path without a trailing separator, so that it has a file name.
fs::path absolutePath(const fs::path& path) {
  fs::path absolute = fs::weakly_canonical(fs::absolute(path));
  return absolute.has_filename() ? absolute : absolute.parent_path();
}

// True when `path` is `folder` or lies inside it.
bool isWithin(const fs::path& path, const fs::path& folder) {
  const fs::path relative = path.lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) {
    text += (text.empty() ? "" : ", ") + item;
  }
  return text;
}

Json chainJson(const FilterChainConfig& chain) {
  Json order = Json::array();
  for (const FilterStage stage : chain.order) {
    order.push_back(stageName(stage));
  }
  return {{"order", order},
          {"pass_through", {{"min_z", chain.pass_through.min_z},
                            {"max_z", chain.pass_through.max_z}}},
          {"radius_outlier", {{"radius", chain.radius_outlier.radius},
                              {"min_neighbors", chain.radius_outlier.min_neighbors}}},
          {"statistical_outlier", {{"mean_k", chain.statistical_outlier.mean_k},
                                   {"stddev_mul", chain.statistical_outlier.stddev_mul}}},
          {"voxel_grid", {{"leaf_size", chain.voxel_grid.leaf_size}}}};
}

Json runJson(const fs::path& objects, const ModelBuildConfig& config, bool mesh) {
  Json run = {{"method", methodName(config.method)},
              {"objects_folder", objects.string()},
              {"point_type", "pcl::PointXYZ: x y z, float32, metres, object frame (origin at "
                             "the centre of the box's bottom face, x forward, y left, z up)"}};
  if (config.method == ConcatenationMethod::kIcp) {
    const IcpConfig& icp = config.icp;
    run["icp"] = {{"max_iterations", icp.max_iterations},
                  {"max_correspondence_distance", icp.max_correspondence_distance},
                  {"transformation_epsilon", icp.transformation_epsilon},
                  {"euclidean_fitness_epsilon", icp.euclidean_fitness_epsilon},
                  {"max_fitness", icp.max_fitness},
                  {"max_translation", icp.max_translation},
                  {"max_rotation_deg", icp.max_rotation_deg},
                  {"min_points", icp.min_points},
                  {"target_leaf_size", icp.target_leaf_size}};
    run["seed"] = {{"objects_per_side", config.seed.objects_per_side}};
  }
  if (mesh) {
    const MeshConfig& settings = config.mesh;
    run["mesh"] = {{"normal_k", settings.normal_k},
                   {"search_radius", settings.search_radius},
                   {"mu", settings.mu},
                   {"max_nearest_neighbors", settings.max_nearest_neighbors},
                   {"max_surface_angle_deg", settings.max_surface_angle_deg},
                   {"min_angle_deg", settings.min_angle_deg},
                   {"max_angle_deg", settings.max_angle_deg}};
  }
  return run;
}

Json classJson(const ClassModelSummary& summary, const std::vector<fs::path>& files,
               const ModelBuildConfig& config, bool written, bool mesh) {
  Json entry = {{"objects", summary.objects}, {"kept", summary.kept}};
  if (config.method == ConcatenationMethod::kIcp && summary.objects > 0) {
    Json seed_objects = Json::array();
    for (const std::size_t index : summary.seed_objects) {
      seed_objects.push_back(files[index].filename().string());
    }
    entry["icp"] = {{"seed", {{"source", summary.seed_source},
                              {"points", summary.seed_points},
                              {"objects", seed_objects},
                              {"missing_sides", summary.missing_sides}}},
                    {"verdicts", summary.verdicts},
                    {"convergence", summary.convergence}};
  }
  entry["raw_points"] = summary.raw_points;
  Json stages = Json::array();
  for (const StageResult& stage : summary.stages) {
    stages.push_back({{"stage", stageName(stage.stage)}, {"points", stage.points}});
  }
  entry["stages"] = stages;
  entry["points"] = summary.points;
  entry["filters"] = chainJson(summary.filters);
  entry["seconds"] = summary.seconds;
  if (written) {
    Json outputs = {{"model", summary.label + ".pcd"}, {"raw", "raw/" + summary.label + ".pcd"}};
    if (mesh) {
      outputs["mesh"] = "mesh/" + summary.label + ".ply";
      entry["mesh_polygons"] = summary.mesh_polygons;
    }
    entry["files"] = outputs;
  }
  entry["warnings"] = summary.warnings;
  return entry;
}

}  // namespace

ClassModel buildClassModel(const std::string& label, const std::vector<ModelCloud>& objects,
                           const ModelBuildConfig& config, const ModelCloud* seed,
                           const std::function<void(std::size_t, std::size_t)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  ClassModel result;
  ClassModelSummary& summary = result.summary;
  summary.label = label;
  summary.objects = objects.size();
  summary.filters = config.filtersFor(label);
  if (objects.empty()) {
    summary.warnings.push_back("no objects of this class");
    return result;
  }

  if (config.method == ConcatenationMethod::kPlain) {
    result.raw = concatenate(objects);
    summary.kept = objects.size();
  } else {
    ModelCloud start_model;
    if (seed != nullptr) {
      summary.seed_source = "file";
      start_model = *seed;
    } else {
      summary.seed_source = "auto";
      const SeedSelection selection = selectSeedObjects(objects, config.seed);
      std::vector<ModelCloud> chosen;
      for (const std::size_t index : selection.indices) {
        chosen.push_back(objects[index]);
      }
      start_model = concatenate(chosen);
      summary.seed_objects = selection.indices;
      for (const Side side : selection.missing_sides) {
        summary.missing_sides.push_back(sideName(side));
      }
      if (objects.size() == 1) {
        summary.warnings.push_back("a single object: ICP has nothing to align, the model is "
                                   "that object");
      } else if (!summary.missing_sides.empty()) {
        summary.warnings.push_back("the automatic ICP seed shows no " +
                                   joined(summary.missing_sides) + " side");
      }
    }
    summary.seed_points = start_model.size();
    IcpConcatenation icp =
        concatenateWithIcp(objects, start_model, summary.seed_objects, config.icp, progress);
    result.raw = std::move(icp.model);
    summary.kept = icp.kept;
    std::vector<bool> in_seed(objects.size(), false);
    for (const std::size_t index : summary.seed_objects) {
      in_seed[index] = true;
    }
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (in_seed[i]) {
        continue;
      }
      const Alignment& alignment = icp.alignments[i];
      ++summary.verdicts[verdictName(alignment.verdict)];
      if (alignment.verdict != IcpVerdict::kTooFewPoints) {
        ++summary.convergence[convergenceName(alignment.convergence)];
      }
    }
  }

  summary.raw_points = result.raw.size();
  result.model = applyFilterChain(result.raw, summary.filters, &summary.stages);
  summary.points = result.model.size();
  if (result.model.empty()) {
    summary.warnings.push_back("the filter chain left no points");
  }
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

BuildModelsSummary buildModels(const fs::path& objects, const fs::path& out,
                               const ModelBuildConfig& config,
                               const BuildModelsOptions& options) {
  validate(config);
  BuildModelsSummary summary;
  std::vector<std::string> unnamed;
  const std::map<std::string, std::vector<fs::path>> files = listObjectFiles(objects, &unnamed);
  if (!unnamed.empty()) {
    summary.warnings.push_back(std::to_string(unnamed.size()) +
                               " PCD file(s) without a class in their name ignored, e.g. " +
                               unnamed.front());
  }
  if (files.empty()) {
    throw std::runtime_error(objects.string() +
                             ": no object PCDs (<Class>-<stamp>-<index>.pcd) in this folder");
  }

  std::set<std::string> labels(options.classes.begin(), options.classes.end());
  if (labels.empty()) {
    for (const auto& [label, paths] : files) {
      labels.insert(label);
    }
  }
  if (std::none_of(labels.begin(), labels.end(),
                   [&](const std::string& label) { return files.count(label) != 0; })) {
    const std::vector<std::string> requested(labels.begin(), labels.end());
    throw std::runtime_error(objects.string() + ": none of the requested classes (" +
                             joined(requested) + ") has objects here");
  }
  for (const auto& [label, file] : options.seeds) {
    if (labels.count(label) == 0) {
      throw std::runtime_error(file.string() + ": seed for class '" + label +
                               "', which is not being built");
    }
  }
  if (!options.seeds.empty() && config.method != ConcatenationMethod::kIcp) {
    summary.warnings.push_back("seed PCDs are used by the icp method only; ignored");
  }

  const fs::path target = absolutePath(out);
  if (isWithin(absolutePath(objects), target)) {
    throw std::runtime_error(target.string() +
                             ": output folder is or holds the objects folder; refusing to "
                             "replace it");
  }
  checkOutputFolder(target, options.output);

  std::map<std::string, ModelCloud> seeds;
  if (config.method == ConcatenationMethod::kIcp) {
    for (const auto& [label, file] : options.seeds) {
      seeds[label] = readModelPcd(file);
      if (seeds[label].empty()) {
        throw std::runtime_error(file.string() + ": seed PCD has no finite points");
      }
    }
  }

  OutputFolder output(target, "build_models", options.output);
  summary.cleared = output.cleared();
  const fs::path& staging = output.staging();
  fs::create_directory(staging / "raw");
  if (options.mesh) {
    fs::create_directory(staging / "mesh");
  }

  Json classes = Json::object();
  for (const std::string& label : labels) {
    const auto found = files.find(label);
    const std::vector<fs::path> paths =
        found == files.end() ? std::vector<fs::path>() : found->second;
    std::vector<ModelCloud> clouds;
    clouds.reserve(paths.size());
    std::size_t non_finite = 0;
    for (const fs::path& path : paths) {
      std::size_t dropped = 0;
      clouds.push_back(toModelCloud(readPcd(path), &dropped));
      non_finite += dropped;
    }

    const auto seed = seeds.find(label);
    std::function<void(std::size_t, std::size_t)> progress;
    if (options.progress) {
      progress = [&](std::size_t done, std::size_t total) {
        options.progress(label, done, total);
      };
    }
    ClassModel model = buildClassModel(label, clouds, config,
                                       seed == seeds.end() ? nullptr : &seed->second, progress);
    ClassModelSummary& result = model.summary;
    if (non_finite > 0) {
      result.warnings.push_back(std::to_string(non_finite) + " non-finite points dropped");
    }
    if (config.method == ConcatenationMethod::kIcp && seed != seeds.end()) {
      result.seed_source = options.seeds.at(label).string();
    }

    const bool written = !model.model.empty();
    if (written) {
      writeModelPcd(staging / modelFileName(label), model.model);
      writeModelPcd(staging / "raw" / modelFileName(label), model.raw);
      if (options.mesh) {
        const pcl::PolygonMesh mesh = triangulate(model.model, config.mesh);
        result.mesh_polygons = mesh.polygons.size();
        writeMeshPly(staging / "mesh" / (encodeLabel(label) + ".ply"), mesh);
      }
    }
    classes[label] = classJson(result, paths, config, written, options.mesh);
    if (options.class_done) {
      options.class_done(result);
    }
    summary.classes.push_back(std::move(result));
  }

  Json document = runJson(absolutePath(objects), config, options.mesh);
  document["classes"] = classes;
  document["warnings"] = summary.warnings;
  writeFile(staging / "models.json", document.dump(2) + "\n", "JSON");
  output.commit();
  return summary;
}

}  // namespace granular
