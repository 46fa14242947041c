#include "granular_core/runs/classify_registration_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/models_folder.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/dataset/registration_results.h"
#include "granular_core/parallel.h"
#include "granular_core/text.h"

namespace granular {
namespace fs = std::filesystem;

namespace {

RegistrationPairRecord pairRecord(const PairResult& result, bool with_transform) {
  RegistrationPairRecord pair;
  pair.converged = result.converged();
  pair.state = registrationStateName(result.state);
  pair.iterations = result.iterations;
  pair.fitness = result.reportedFitness();
  if (pair.fitness) {
    pair.inlier_shares.assign(result.inlier_shares.begin(), result.inlier_shares.end());
  }
  pair.rejected = result.rejected;
  if (with_transform && result.ran()) {
    std::array<float, 16>& transform = pair.transform.emplace();
    for (int row = 0; row < 4; ++row) {
      for (int column = 0; column < 4; ++column) {
        transform[static_cast<std::size_t>(row * 4 + column)] = result.transform(row, column);
      }
    }
  }
  return pair;
}

}  // namespace


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

void ClassificationRun::report(std::ostream& out) const {
  char line[200];
  std::snprintf(line, sizeof(line), "%s (%s): %zu objects against %zu models in %.2f s on %d threads\n",
                registrationMethodName(method), preset.c_str(), objects.size(), models.size(),
                seconds, threads);
  out << line;
  for (int criterion = 1; criterion <= 3; ++criterion) {
    const CriterionSummary counts = summary(criterion);
    std::snprintf(line, sizeof(line),
                  "  criterion %d: %zu predicted, %zu without a prediction, accuracy %.3f of "
                  "the predicted\n",
                  criterion, counts.predicted, counts.missing, counts.accuracy());
    out << line;
  }
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

  // Read on the registration's threads: thousands of small files, each parsed on its own.
  // A file that cannot be read stops the run, the first such in the folder's order named.
  std::vector<ModelCloud> clouds(files.size());
  parallelFor(files.size(), registrationThreads(options.registration), 16,
              [&](std::size_t i) { clouds[i] = readModelPcd(files[i]); });
  run.objects.resize(files.size());
  std::size_t points = 0;
  std::size_t below = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    ObjectRecord& record = run.objects[i];
    record.file = files[i].filename().string();
    record.true_label = objectClass(files[i]);
    record.points = clouds[i].size();
    record.points_used = registrationSourceSize(clouds[i], config);
    points += clouds[i].size();
    below += pointsBelow(clouds[i], kBoxCentredDepth);
  }
  if (points > 0 &&
      static_cast<double>(below) > kBoxCentredShare * static_cast<double>(points)) {
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

void writeClassificationJson(const fs::path& file, const ClassificationRun& run,
                             const ClassificationJsonOptions& options) {
  RegistrationResultsFile results;
  results.method = registrationMethodName(run.method);
  results.preset = run.preset;
  results.parameters = registrationParameters(run.method, run.config).dump();
  results.models = run.models;
  results.inlier_radii.emplace(kInlierRadii.begin(), kInlierRadii.end());
  results.seconds = run.seconds;
  results.threads = run.threads;
  results.transforms = options.transforms;
  for (const ObjectRecord& object : run.objects) {
    RegistrationObjectRecord& record = results.objects.emplace_back();
    record.file = object.file;
    if (!object.true_label.empty()) {
      record.true_label = object.true_label;
    }
    record.points = object.points;
    record.points_used = object.points_used;
    for (const PairResult& pair : object.per_model) {
      record.per_model.push_back(pairRecord(pair, options.transforms));
    }
    for (int criterion = 1; criterion <= 3; ++criterion) {
      if (const auto& prediction = object.predictions.criterion(criterion)) {
        record.predictions[static_cast<std::size_t>(criterion - 1)] = run.models.at(*prediction);
      }
    }
  }
  for (int criterion = 1; criterion <= 3; ++criterion) {
    const CriterionSummary summary = run.summary(criterion);
    results.criteria[static_cast<std::size_t>(criterion - 1)] = {
        summary.predicted, summary.missing, summary.labelled, summary.correct, summary.accuracy()};
  }
  results.warnings = run.warnings;
  writeRegistrationResults(file, results);
}

}  // namespace granular
