#include "granular_core/classification/classify_folder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/models/model_cloud.h"

namespace granular {
namespace fs = std::filesystem;

namespace {

constexpr double kBoxCentredDepth = -0.1;     // m
constexpr double kBoxCentredFraction = 0.1;

std::size_t pointsBelow(const ModelCloud& cloud, double z) {
  return static_cast<std::size_t>(std::count_if(
      cloud.points.begin(), cloud.points.end(),
      [z](const pcl::PointXYZ& point) { return point.z < z; }));
}

std::string percent(double fraction) {
  std::ostringstream text;
  text.precision(0);
  text << std::fixed << fraction * 100.0 << "%";
  return text.str();
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) {
    text += (text.empty() ? "" : ", ") + item;
  }
  return text;
}

bool isPcd(const fs::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  return entry.is_regular_file() && entry.path().extension() == ".pcd" && name[0] != '.';
}

nlohmann::json parameters(RegistrationMethod method, const RegistrationClassifierConfig& config) {
  nlohmann::json json;
  if (method == RegistrationMethod::kNdt) {
    const NdtClassifierConfig& ndt = config.ndt;
    json = {{"transformation_epsilon", ndt.transformation_epsilon},
            {"step_size", ndt.step_size},
            {"max_iterations", ndt.max_iterations},
            {"resolution", ndt.resolution},
            {"min_points_per_voxel", ndt.min_points_per_voxel},
            {"outlier_ratio", ndt.outlier_ratio}};
  } else {
    const IcpClassifierConfig& icp =
        method == RegistrationMethod::kIcp ? config.icp : config.icp_nl;
    json = {{"max_iterations", icp.max_iterations},
            {"max_correspondence_distance", icp.max_correspondence_distance},
            {"transformation_epsilon", icp.transformation_epsilon},
            {"euclidean_fitness_epsilon", icp.euclidean_fitness_epsilon}};
  }
  json["source_min_z"] =
      config.source_min_z ? nlohmann::json(*config.source_min_z) : nlohmann::json(nullptr);
  json["min_source_points"] = minimumSourcePoints(method);
  return json;
}

nlohmann::json pairJson(const PairResult& result) {
  nlohmann::json json = {{"converged", result.converged()},
                         {"state", registrationStateName(result.state)},
                         {"iterations", result.iterations}};
  if (result.ran() && std::isfinite(result.fitness)) {
    json["fitness"] = result.fitness;
  } else {
    json["fitness"] = nullptr;
  }
  if (result.ran()) {
    nlohmann::json transform = nlohmann::json::array();
    for (int row = 0; row < 4; ++row) {
      for (int column = 0; column < 4; ++column) {
        transform.push_back(result.transform(row, column));
      }
    }
    json["transform"] = transform;
  } else {
    json["transform"] = nullptr;
  }
  return json;
}

}  // namespace

bool looksBoxCentred(const ModelCloud& cloud) {
  return !cloud.empty() && static_cast<double>(pointsBelow(cloud, kBoxCentredDepth)) >
                               kBoxCentredFraction * static_cast<double>(cloud.size());
}

std::vector<LabelledModel> readClassModels(const fs::path& folder) {
  if (fs::is_regular_file(folder)) {
    throw std::runtime_error(folder.string() + ": is a file (a classifier from "
                                               "train_classifier?); the registration methods "
                                               "(icp, icp_nl, ndt) need a models folder written "
                                               "by build_models");
  }
  if (!fs::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": no such models folder");
  }
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (isPcd(entry)) {
      files.push_back(entry.path());
    }
  }
  if (files.empty()) {
    throw std::runtime_error(folder.string() +
                             ": no class models (<Class>.pcd) in this folder");
  }
  std::sort(files.begin(), files.end());
  std::vector<LabelledModel> models;
  for (const fs::path& file : files) {
    LabelledModel model{modelClass(file), readModelPcd(file)};
    if (model.label.empty()) {
      throw std::runtime_error(file.string() + ": not a class model's name (<Class>.pcd, the "
                                               "class written as build_models writes it)");
    }
    if (model.cloud.empty()) {
      throw std::runtime_error(file.string() + ": the model has no points");
    }
    if (looksBoxCentred(model.cloud)) {
      const double fraction = static_cast<double>(pointsBelow(model.cloud, kBoxCentredDepth)) /
                              static_cast<double>(model.cloud.size());
      throw std::runtime_error(
          file.string() + ": " + percent(fraction) +
          " of the model's points lie below z = -0.1 m: it is in a box-centre frame (z = 0 at "
          "half the box's height), not the object frame of the objects (z = 0 on the road, "
          "the object above it). Rebuild the models from objects extracted by "
          "extract_objects (build_models).");
    }
    models.push_back(std::move(model));
  }
  return models;
}

double CriterionSummary::accuracy() const {
  return labelled == 0 ? 0.0 : static_cast<double>(correct) / static_cast<double>(labelled);
}

CriterionSummary ClassificationRun::summary(int criterion) const {
  CriterionSummary summary;
  for (const ObjectRecord& object : objects) {
    const std::optional<std::size_t>& prediction = object.predictions.criterion(criterion);
    if (!prediction) {
      ++summary.missing;
      continue;
    }
    ++summary.predicted;
    if (!object.true_label.empty()) {
      ++summary.labelled;
      if (models.at(*prediction) == object.true_label) {
        ++summary.correct;
      }
    }
  }
  return summary;
}

ClassificationRun classifyFolder(const fs::path& models, const fs::path& objects,
                                 RegistrationMethod method,
                                 const RegistrationClassifierConfig& config,
                                 const ClassifyFolderOptions& options) {
  validate(config);
  ClassificationRun run;
  run.method = method;
  run.preset = options.preset;
  run.config = config;
  const auto warn = [&](const std::string& warning) {
    run.warnings.push_back(warning);
    if (options.warn) {
      options.warn(warning);
    }
  };

  std::vector<LabelledModel> class_models = readClassModels(models);
  for (const LabelledModel& model : class_models) {
    run.models.push_back(model.label);
  }

  std::map<std::string, std::vector<fs::path>> by_class;
  const std::vector<fs::path> files = listAllObjectFiles(objects, &by_class);
  std::vector<std::string> unnamed;
  for (const fs::path& file : files) {
    if (objectClass(file).empty()) {
      unnamed.push_back(file.filename().string());
    }
  }

  std::vector<std::string> without_model;
  for (const auto& [label, paths] : by_class) {
    if (std::find(run.models.begin(), run.models.end(), label) == run.models.end()) {
      without_model.push_back(label + " (" + std::to_string(paths.size()) + ")");
    }
  }
  if (!without_model.empty()) {
    warn("objects of classes without a model in " + models.string() + ": " +
         joined(without_model) + "; they are predicted among the models there are (" +
         joined(run.models) + ") and count as wrong");
  }
  if (!unnamed.empty()) {
    warn(std::to_string(unnamed.size()) +
         " object PCD(s) without a class in their name (e.g. " + unnamed.front() +
         ") are classified without a true label");
  }

  std::vector<ModelCloud> clouds(files.size());
  run.objects.resize(files.size());
  std::size_t points = 0;
  std::size_t below = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    clouds[i] = readModelPcd(files[i]);
    ObjectRecord& record = run.objects[i];
    record.file = files[i].filename().string();
    record.true_label = objectClass(files[i]);
    record.points = clouds[i].size();
    record.points_used =
        config.source_min_z ? clouds[i].size() - pointsBelow(clouds[i], *config.source_min_z)
                            : clouds[i].size();
    points += clouds[i].size();
    below += pointsBelow(clouds[i], kBoxCentredDepth);
  }
  if (points > 0 &&
      static_cast<double>(below) > kBoxCentredFraction * static_cast<double>(points)) {
    warn(percent(static_cast<double>(below) / static_cast<double>(points)) +
         " of the object points lie below z = -0.1 m: the objects look box-centred (z = 0 at "
         "half the box's height), while the models are in the object frame (z = 0 on the "
         "road); expect poor matches");
  }

  const auto start = std::chrono::steady_clock::now();
  const RegistrationClassifier classifier(method, config, std::move(class_models));
  for (const std::string& warning : classifier.warnings()) {
    warn(warning);
  }
  const std::vector<std::vector<PairResult>> results =
      classifier.registerObjects(clouds, options.registration);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.threads = registrationThreads(options.registration);

  for (std::size_t i = 0; i < results.size(); ++i) {
    run.objects[i].per_model = results[i];
    run.objects[i].predictions = predict(results[i]);
  }
  return run;
}

void writeClassificationJson(const fs::path& file, const ClassificationRun& run) {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectRecord& object : run.objects) {
    nlohmann::json per_model = nlohmann::json::object();
    for (std::size_t m = 0; m < object.per_model.size(); ++m) {
      per_model[run.models.at(m)] = pairJson(object.per_model[m]);
    }
    nlohmann::json predictions = nlohmann::json::object();
    for (int criterion = 1; criterion <= 3; ++criterion) {
      const std::optional<std::size_t>& prediction = object.predictions.criterion(criterion);
      predictions["criterion" + std::to_string(criterion)] =
          prediction ? nlohmann::json(run.models.at(*prediction)) : nlohmann::json(nullptr);
    }
    objects.push_back({{"file", object.file},
                       {"true_label", object.true_label.empty()
                                          ? nlohmann::json(nullptr)
                                          : nlohmann::json(object.true_label)},
                       {"points", object.points},
                       {"points_used", object.points_used},
                       {"per_model", per_model},
                       {"predictions", predictions}});
  }
  nlohmann::json missing = nlohmann::json::object();
  nlohmann::json accuracy = nlohmann::json::object();
  for (int criterion = 1; criterion <= 3; ++criterion) {
    const std::string key = "criterion" + std::to_string(criterion);
    const CriterionSummary summary = run.summary(criterion);
    missing[key] = summary.missing;
    accuracy[key] = {{"predicted", summary.predicted},
                     {"labelled", summary.labelled},
                     {"correct", summary.correct},
                     {"accuracy", summary.accuracy()}};
  }
  const nlohmann::json document = {{"method", registrationMethodName(run.method)},
                                   {"preset", run.preset},
                                   {"parameters", parameters(run.method, run.config)},
                                   {"models", run.models},
                                   {"seconds", run.seconds},
                                   {"threads", run.threads},
                                   {"objects", objects},
                                   {"missing", missing},
                                   {"accuracy", accuracy},
                                   {"warnings", run.warnings}};

  writeFileAtomically(file, document.dump(1) + "\n", "JSON");
}

}  // namespace granular
