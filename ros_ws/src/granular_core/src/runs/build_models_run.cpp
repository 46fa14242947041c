#include "granular_core/runs/build_models_run.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <set>
#include <stdexcept>
#include <system_error>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/objects_index.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/models/concatenate.h"
#include "granular_core/models/icp_concatenate.h"
#include "granular_core/dataset/mesh_ply.h"
#include "granular_core/models/mesh.h"
#include "granular_core/text.h"

namespace granular {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;


// The absolute path without a trailing separator, so that it has a file name.
fs::path absolutePath(const fs::path& path) {
  fs::path absolute = fs::weakly_canonical(fs::absolute(path));
  return absolute.has_filename() ? absolute : absolute.parent_path();
}

Json runJson(const fs::path& objects, const ModelBuildConfig& config, bool mesh) {
  Json run = {{"method", methodName(config.method)},
              {"objects_folder", objects.string()},
              {"min_objects", config.min_objects},
              {"min_points", config.min_points},
              {"point_type", "pcl::PointXYZ: x y z, float32, metres, object frame (origin at "
                             "the centre of the box's bottom face, x forward, y left, z up)"}};
  if (config.method == ConcatenationMethod::kIcp) {
    run["icp"] = config::toJson(config.icp);
    run["seed"] = config::toJson(config.seed);
  }
  if (mesh) {
    run["mesh"] = config::toJson(config.mesh);
  }
  return run;
}

Json classJson(const ClassModelSummary& summary, const std::vector<fs::path>& files,
               const ModelBuildConfig& config, bool written, bool mesh,
               const std::string& left_out) {
  Json entry = {{"objects", summary.objects}, {"kept", summary.kept}};
  if (!left_out.empty()) {
    entry["left_out"] = left_out;
  }
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
  entry["filters"] = config::toJson(summary.filters);
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

// Which filter emptied a class's model, and what to change.
std::string emptiedMessage(const ClassModelSummary& model) {
  const std::string key = "class_filters." + model.label + ".";
  std::string advice;
  switch (*model.emptied_by) {
    case FilterStage::kPassThrough:
      advice = "widen " + key + "pass_through (min_z, max_z)";
      break;
    case FilterStage::kRadiusOutlier:
      advice = "raise " + key + "radius_outlier.radius or lower its min_neighbors";
      break;
    case FilterStage::kStatisticalOutlier:
      advice = "raise " + key + "statistical_outlier.stddev_mul";
      break;
    case FilterStage::kVoxelGrid:
      advice = "check " + key + "voxel_grid";
      break;
  }
  return "the filters left no points (" + std::to_string(model.raw_points) +
         " before filtering): the " + stageName(*model.emptied_by) +
         " stage removed them all; " + advice + ", leave the stage out of " + key +
         "order";
}

// Why class `model` gets no model, or "" when it has enough data (ModelBuildConfig's
// min_objects and min_points).
std::string leftOutReason(const ClassModelSummary& model, const ModelBuildConfig& config) {
  if (model.objects == 0) {
    return "no objects";
  }
  if (model.objects < config.min_objects) {
    return std::to_string(model.objects) + " object(s), fewer than min_objects " +
           std::to_string(config.min_objects);
  }
  if (model.emptied_by) {
    return emptiedMessage(model);
  }
  if (model.points < config.min_points) {
    return "a model of " + std::to_string(model.points) + " points, fewer than min_points " +
           std::to_string(config.min_points);
  }
  return "";
}

}  // namespace

void BuildModelsSummary::reportClass(const ClassModelSummary& model, std::ostream& log) {
  log << model.label << ": " << model.objects << " objects, " << model.kept << " kept, "
      << model.raw_points << " raw points, " << model.points << " model points, " << std::fixed
      << std::setprecision(2) << model.seconds << " s\n";
  for (const std::string& warning : model.warnings) {
    log << model.label << ": warning: " << warning << '\n';
  }
}

void BuildModelsSummary::report(std::ostream& out, std::ostream& log) const {
  for (const std::string& line : cleared) {
    log << "cleared: " << line << '\n';
  }
  for (const std::string& warning : warnings) {
    log << "warning: " << warning << '\n';
  }
  out << "models (" << methodName(method)
      << " concatenation; points after each filter stage, '-' not run):\n";
  // The class column as wide as the longest label, so that long real labels keep the table.
  int width = 12;
  for (const ClassModelSummary& model : classes) {
    width = std::max(width, static_cast<int>(model.label.size()));
  }
  out << "  " << std::left << std::setw(width) << "class" << std::right << ' ' << std::setw(8)
      << "objects" << ' ' << std::setw(8) << "kept" << ' ' << std::setw(9) << "raw";
  for (const auto& [stage, name] : config::EnumNames<FilterStage>::values) {
    out << ' ' << std::setw(19) << name;
  }
  out << ' ' << std::setw(8) << "seconds" << '\n';
  for (const ClassModelSummary& model : classes) {
    out << "  " << std::left << std::setw(width) << model.label << std::right << ' '
        << std::setw(8) << model.objects << ' ' << std::setw(8) << model.kept << ' '
        << std::setw(9) << model.raw_points;
    for (const auto& [stage, name] : config::EnumNames<FilterStage>::values) {
      std::string cell = "-";
      for (const StageResult& result : model.stages) {
        if (result.stage == stage) {
          cell = std::to_string(result.points);
        }
      }
      out << ' ' << std::setw(19) << cell;
    }
    out << ' ' << std::setw(8) << std::fixed << std::setprecision(2) << model.seconds << '\n';
  }
  out << "total: " << classes.size() - left_out.size() << " class models";
  if (!left_out.empty()) {
    std::vector<std::string> names;
    for (const auto& [label, reason] : left_out) {
      names.push_back(label);
    }
    out << ", " << left_out.size() << " classes left out (" << joined(names)
        << "; the warnings say why)";
  }
  out << ", " << std::fixed << std::setprecision(2) << seconds << " s\n";
}

BuildModelsSummary buildModels(const fs::path& objects, const fs::path& out,
                               const ModelBuildConfig& config,
                               const BuildModelsOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(config);
  BuildModelsSummary summary;
  summary.method = config.method;
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
  // A class_filters entry for a class that is not here is a typo more often than not (the
  // built-in entries are for the simulator's classes, absent from other data).
  const FilterChainOverrides built_in = defaultClassFilters();
  std::vector<std::string> present;
  for (const auto& [label, paths] : files) {
    present.push_back(label);
  }
  for (const auto& [label, change] : config.class_filters.by_name) {
    if (files.count(label) == 0 && built_in.by_name.count(label) == 0) {
      summary.warnings.push_back("class_filters." + label + ": no objects of class '" + label +
                                 "' here, so these filter changes are unused (classes: " +
                                 joined(present) + ")");
    }
  }
  // The box heights of each class, for an automatic pass-through band.
  std::map<std::string, std::vector<double>> box_heights;
  for (const ObjectIndexRow& row : readObjectIndex(objects)) {
    box_heights[row.label].push_back(row.height);
  }

  const fs::path target = absolutePath(out);
  checkOutputApart(target, {objects});
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

  OutputFolder output(target, "build_models", options.output, {objects});
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
    if (!paths.empty() && paths.size() < config.min_objects) {
      // Too few objects to be worth reading.
      ClassModelSummary result;
      result.label = label;
      result.objects = paths.size();
      const std::string reason = leftOutReason(result, config);
      result.warnings.push_back("left out: " + reason);
      summary.left_out[label] = reason;
      classes[label] = classJson(result, paths, config, false, options.mesh, reason);
      if (options.class_done) {
        options.class_done(result);
      }
      summary.classes.push_back(std::move(result));
      continue;
    }
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
    ClassModel model;
    try {
      model = buildClassModel(label, clouds, config,
                              seed == seeds.end() ? nullptr : &seed->second, progress,
                              box_heights[label]);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error("class '" + label + "': " + error.what());
    }
    ClassModelSummary& result = model.summary;
    if (non_finite > 0) {
      result.warnings.push_back(std::to_string(non_finite) + " non-finite points dropped");
    }
    const std::string reason = leftOutReason(result, config);
    if (!reason.empty()) {
      result.warnings.push_back("left out: " + reason);
      summary.left_out[label] = reason;
    }
    if (config.method == ConcatenationMethod::kIcp && seed != seeds.end()) {
      result.seed_source = options.seeds.at(label).string();
    }

    const bool written = reason.empty();
    if (written) {
      writeModelPcd(staging / modelFileName(label), model.model);
      writeModelPcd(staging / "raw" / modelFileName(label), model.raw);
      if (options.mesh) {
        const pcl::PolygonMesh mesh = triangulate(model.model, config.mesh);
        result.mesh_polygons = mesh.polygons.size();
        writeMeshPly(staging / "mesh" / (encodeLabel(label) + ".ply"), mesh);
      }
    }
    classes[label] = classJson(result, paths, config, written, options.mesh, reason);
    if (options.class_done) {
      options.class_done(result);
    }
    summary.classes.push_back(std::move(result));
  }

  if (summary.left_out.size() == summary.classes.size()) {
    std::vector<std::string> reasons;
    for (const auto& [label, reason] : summary.left_out) {
      reasons.push_back("class '" + label + "': " + reason);
    }
    throw std::runtime_error("no class has enough data for a model: " + joined(reasons, "; "));
  }
  for (const auto& [label, reason] : summary.left_out) {
    summary.warnings.push_back("class '" + label + "' left out (no model): " + reason);
  }
  Json document = runJson(absolutePath(objects), config, options.mesh);
  document["classes"] = classes;
  document["left_out"] = summary.left_out;
  document["warnings"] = summary.warnings;
  writeFile(staging / "models.json", document.dump(2) + "\n", "JSON");
  output.commit();
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace granular
