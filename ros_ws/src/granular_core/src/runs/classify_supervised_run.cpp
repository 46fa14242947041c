// The runs of train_classifier and classify_supervised: folder features, svm_fitness's features
// from registration results files, training, classifying and the results JSON. (Over 400
// lines: the two tools share the private feature and timing helpers here.)
#include "granular_core/runs/classify_supervised_run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/dataset/registration_results.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/parallel.h"
#include "granular_core/text.h"

namespace granular {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

// Objects handed to a thread at a time: each costs a file read and its features.
constexpr int kObjectsPerChunk = 8;

double microsecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

std::size_t finitePoints(const Cloud& cloud) {
  return static_cast<std::size_t>(std::count_if(
      cloud.points.begin(), cloud.points.end(), [](const PointXYZIT& p) {
        return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      }));
}

void addWarnings(SupervisedRun& run, const SupervisedClassifier& classifier) {
  const std::set<std::string> known(classifier.labels().begin(), classifier.labels().end());
  std::map<std::string, std::size_t> unknown;
  std::size_t small = 0;
  const std::vector<std::string>& files = run.files;
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (!run.true_labels[i].empty() && known.count(run.true_labels[i]) == 0) {
      ++unknown[run.true_labels[i]];
    }
    small += run.points[i] < 3;
  }
  for (const auto& [label, count] : unknown) {
    run.warnings.push_back(std::to_string(count) + " object(s) of class " + label +
                           ", which the classifier was not trained on; they count as wrong");
  }
  if (small > 0) {
    run.warnings.push_back(std::to_string(small) +
                           " object(s) with fewer than 3 points, classified from what they have");
  }
}

// One classify_registration results file as svm_fitness needs it: what ran, and each object's
// fitness per model.
struct RegistrationResults {
  std::string method, preset;
  nlohmann::json parameters;
  std::vector<std::string> models;
  double seconds = 0.0;
  std::vector<std::string> files;
  std::vector<std::size_t> points;
  std::vector<std::vector<PairFitness>> pairs;  // [object][model]
  /// The file records inlier shares (its inlier_radii; files before them did not).
  bool inlier_shares = true;
};

// A results file (dataset/registration_results) as svm_fitness learns from it: each pair's
// fitness and inlier shares, checked for what the features need.
RegistrationResults readFitness(const fs::path& file) {
  const auto fail = [&](const std::string& what) {
    return std::runtime_error(file.string() + ": " + what);
  };
  const RegistrationResultsFile read = readRegistrationResults(file);
  RegistrationResults results;
  results.method = read.method;
  results.preset = read.preset;
  results.parameters = nlohmann::json::parse(read.parameters);
  results.models = read.models;
  results.seconds = read.seconds;
  results.inlier_shares = read.inlier_radii.has_value();
  if (read.inlier_radii &&
      *read.inlier_radii != std::vector<double>(kInlierRadii.begin(), kInlierRadii.end())) {
    throw fail("inlier shares measured at " + nlohmann::json(*read.inlier_radii).dump() +
               " m, not at the radii this granular uses; register again");
  }
  for (const RegistrationObjectRecord& object : read.objects) {
    results.files.push_back(object.file);
    results.points.push_back(object.points);
    std::vector<PairFitness>& pairs = results.pairs.emplace_back();
    for (std::size_t m = 0; m < read.models.size(); ++m) {
      const RegistrationPairRecord& pair = object.per_model[m];
      if (pair.rejected) {
        throw fail("written with --early-rejection: the fitness of the models that could not "
                   "win was not computed, and svm_fitness's features need every model's");
      }
      PairFitness& fitness = pairs.emplace_back();
      if (!pair.fitness) {
        continue;
      }
      fitness.fitness = *pair.fitness;
      if (results.inlier_shares) {
        if (pair.inlier_shares.size() != kInlierRadii.size()) {
          throw fail(object.file + ": " + read.models[m] + ": " +
                     std::to_string(pair.inlier_shares.size()) +
                     " inlier shares, not one per radius");
        }
        std::copy(pair.inlier_shares.begin(), pair.inlier_shares.end(),
                  fitness.inlier_shares.begin());
      }
    }
  }
  if (results.files.empty() || results.models.empty()) {
    throw fail("holds no objects or no models");
  }
  return results;
}

// Throws unless the results files were registered as those the classifier learnt from.
void requireSameSources(const std::string& trained, const std::string& given,
                        const std::vector<fs::path>& results) {
  const nlohmann::json expected = nlohmann::json::parse(trained);
  const nlohmann::json actual = nlohmann::json::parse(given);
  const auto methods = [](const nlohmann::json& sources) {
    std::string list;
    for (const nlohmann::json& source : sources) {
      list += (list.empty() ? "" : ", ") + source.at("method").get<std::string>();
    }
    return list;
  };
  if (expected.size() != actual.size()) {
    throw std::runtime_error("the classifier learnt from " + std::to_string(expected.size()) +
                             " registration results (" + methods(expected) + "), got " +
                             std::to_string(actual.size()) + " (" + methods(actual) + ")");
  }
  for (std::size_t f = 0; f < expected.size(); ++f) {
    for (const char* key : {"method", "parameters", "models"}) {
      if (expected[f].at(key) != actual[f].at(key)) {
        throw std::runtime_error(results[f].string() + ": registered with other " + key +
                                 " than the classifier's results file " + std::to_string(f + 1) +
                                 " (" + expected[f].at(key).dump() + " vs " +
                                 actual[f].at(key).dump() +
                                 "); classify with the same methods, presets and models");
      }
    }
  }
}

}  // namespace

FolderFeatures computeFolderFeatures(const fs::path& folder, FeatureKind kind,
                                     const PointHistogramConfig& config, int threads,
                                     const std::function<void(std::size_t, std::size_t)>& progress) {
  validate(config);
  const std::vector<fs::path> files = listAllObjectFiles(folder);
  FolderFeatures result;
  result.files.resize(files.size());
  result.labels.resize(files.size());
  result.points.resize(files.size());
  result.features.resize(files.size());
  result.microseconds.resize(files.size());
  parallelFor(
      files.size(), threads, kObjectsPerChunk,
      [&](std::size_t i) {
        const Cloud object = readPcd(files[i]);
        const auto start = Clock::now();
        result.features[i] = objectFeatures(object, kind, config);
        result.microseconds[i] = microsecondsSince(start);
        result.files[i] = files[i].filename().string();
        result.labels[i] = objectClass(files[i]);
        result.points[i] = finitePoints(object);
      },
      progress);
  return result;
}

SupervisedRun classifyFolderSupervised(const SupervisedClassifier& classifier,
                                       const fs::path& folder, int threads,
                                       const std::function<void(std::size_t, std::size_t)>& progress) {
  const auto start = Clock::now();
  const std::vector<fs::path> files = listAllObjectFiles(folder);
  SupervisedRun run;
  run.method = classifier.method();
  run.files.resize(files.size());
  run.true_labels.resize(files.size());
  run.points.resize(files.size());
  run.predicted.resize(files.size());
  std::vector<double> microseconds(files.size());
  parallelFor(
      files.size(), threads, kObjectsPerChunk,
      [&](std::size_t i) {
        const Cloud object = readPcd(files[i]);
        const auto begin = Clock::now();
        run.predicted[i] = classifier.predict(classifier.features(object));
        microseconds[i] = microsecondsSince(begin);
        run.files[i] = files[i].filename().string();
        run.true_labels[i] = objectClass(files[i]);
        run.points[i] = finitePoints(object);
      },
      progress);
  run.seconds = microsecondsSince(start) / 1e6;
  run.microseconds_per_object =
      std::accumulate(microseconds.begin(), microseconds.end(), 0.0) / files.size();
  addWarnings(run, classifier);
  return run;
}

RegistrationFeatures readRegistrationFeatures(const std::vector<fs::path>& results,
                                              bool inlier_shares) {
  if (results.empty()) {
    throw std::invalid_argument("no registration results files");
  }
  RegistrationFeatures features;
  nlohmann::json sources = nlohmann::json::array();
  std::vector<std::vector<std::vector<PairFitness>>> pairs;  // [object][file][model]
  std::vector<std::string> share_names;
  for (std::size_t f = 0; f < results.size(); ++f) {
    const auto start = Clock::now();
    const RegistrationResults file = readFitness(results[f]);
    if (inlier_shares && !file.inlier_shares) {
      throw std::runtime_error(
          results[f].string() + ": records no inlier shares (an earlier classify_registration "
          "wrote it): register again, or use a classifier trained with svm_fitness.inlier_shares "
          "false");
    }
    features.registration_seconds += file.seconds;
    sources.push_back({{"method", file.method},
                       {"preset", file.preset},
                       {"parameters", file.parameters},
                       {"models", file.models}});
    for (const std::string& model : file.models) {
      const std::string name = file.method + "/" + file.preset + ":" + model;
      features.origin.names.push_back(name);
      for (std::size_t r = 0; inlier_shares && r < kInlierRadii.size(); ++r) {
        share_names.push_back(inlierShareFeatureName(name, r));
      }
    }
    if (f == 0) {
      features.folder.files = file.files;
      features.folder.points = file.points;
      pairs.resize(file.files.size());
      for (const std::string& name : file.files) {
        features.folder.labels.push_back(objectClass(name));
      }
    } else if (file.files != features.folder.files) {
      throw std::runtime_error(results[f].string() + ": lists other objects than " +
                               results.front().string() +
                               "; give the results of one objects folder");
    }
    for (std::size_t i = 0; i < file.files.size(); ++i) {
      pairs[i].push_back(file.pairs[i]);
    }
    // Reading is shared by the objects: its time goes to each in equal parts.
    const double share = microsecondsSince(start) / static_cast<double>(file.files.size());
    features.folder.microseconds.resize(file.files.size(), 0.0);
    for (double& microseconds : features.folder.microseconds) {
      microseconds += share;
    }
  }
  features.origin.names.push_back("log_points");
  features.origin.names.insert(features.origin.names.end(), share_names.begin(),
                               share_names.end());
  features.origin.source = sources.dump();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    features.folder.features.push_back(
        registrationFitnessFeatures(pairs[i], features.folder.points[i], inlier_shares));
  }
  return features;
}

namespace {

// svm_fitness's point histograms: each listed object's, from its PCD in `objects`, appended to
// its features (and the time to its microseconds).
void appendPointHistograms(FolderFeatures& folder, const fs::path& objects,
                           const PointHistogramConfig& config, int threads) {
  if (objects.empty()) {
    throw std::invalid_argument(
        "svm_fitness with point histograms (svm_fitness.histogram_weight above 0) needs the "
        "objects the registration results are of: give their folder (--objects)");
  }
  requireObjectsFolder(objects);
  parallelFor(
      folder.files.size(), threads, kObjectsPerChunk,
      [&](std::size_t i) {
        const Cloud object = readPcd(objects / folder.files[i]);
        const auto start = Clock::now();
        const std::vector<float> histogram = pointHistogramFeatures(object, config);
        folder.features[i].insert(folder.features[i].end(), histogram.begin(), histogram.end());
        folder.microseconds[i] += microsecondsSince(start);
      });
}

// Keeps the objects of `classes` in `folder` (every object when `classes` is empty). Throws
// std::runtime_error naming a class of `classes` without objects in `source`.
void keepClasses(FolderFeatures& folder, const std::vector<std::string>& classes,
                 const std::string& source) {
  if (classes.empty()) {
    return;
  }
  const std::set<std::string> present(folder.labels.begin(), folder.labels.end());
  for (const std::string& label : classes) {
    if (present.count(label) == 0) {
      throw std::runtime_error(source + ": no objects of class '" + label + "' (classes: " +
                               joined(std::vector<std::string>(present.begin(), present.end())) +
                               ")");
    }
  }
  const std::set<std::string> wanted(classes.begin(), classes.end());
  FolderFeatures kept;
  for (std::size_t i = 0; i < folder.files.size(); ++i) {
    if (wanted.count(folder.labels[i]) != 0) {
      kept.files.push_back(std::move(folder.files[i]));
      kept.labels.push_back(std::move(folder.labels[i]));
      kept.points.push_back(folder.points[i]);
      kept.features.push_back(std::move(folder.features[i]));
      kept.microseconds.push_back(folder.microseconds[i]);
    }
  }
  folder = std::move(kept);
}

}  // namespace

TrainingRun trainOnRegistration(const std::vector<fs::path>& results,
                                const SupervisedConfig& config, const fs::path& objects,
                                int threads, const std::vector<std::string>& classes) {
  validate(config);
  RegistrationFeatures features =
      readRegistrationFeatures(results, config.svm_fitness.inlier_shares);
  if (config.svm_fitness.histogram_weight > 0.0) {
    appendPointHistograms(features.folder, objects, config.histograms, threads);
    const std::vector<std::string> names = pointHistogramFeatureNames(config.histograms);
    features.origin.names.insert(features.origin.names.end(), names.begin(), names.end());
  }
  keepClasses(features.folder, classes, results.front().string());
  TrainingSummary summary;
  SupervisedClassifier classifier =
      SupervisedClassifier::train(SupervisedMethod::kSvmFitness, config, features.folder.features,
                                  features.folder.labels, &summary, features.origin);
  return {std::move(classifier), summary};
}

SupervisedRun classifyRegistrationResults(const SupervisedClassifier& classifier,
                                          const std::vector<fs::path>& results,
                                          const fs::path& objects, int threads) {
  if (featureKindOf(classifier.method()) != FeatureKind::kRegistrationFitness) {
    throw std::invalid_argument(std::string(supervisedMethodName(classifier.method())) +
                                " classifies object clouds, not registration results");
  }
  const auto start = Clock::now();
  RegistrationFeatures features = readRegistrationFeatures(results, classifier.takesInlierShares());
  requireSameSources(classifier.featureOrigin().source, features.origin.source, results);
  if (classifier.takesPointHistograms()) {
    appendPointHistograms(features.folder, objects, classifier.config().histograms, threads);
  }
  SupervisedRun run;
  run.method = classifier.method();
  run.files = features.folder.files;
  run.true_labels = features.folder.labels;
  run.points = features.folder.points;
  run.registration_seconds = features.registration_seconds;
  const auto predicting = Clock::now();
  for (const SupervisedPrediction& prediction :
       classifier.predictWithScores(features.folder.features)) {
    run.predicted.push_back(prediction.label);
  }
  run.seconds = microsecondsSince(start) / 1e6;
  run.microseconds_per_object =
      (std::accumulate(features.folder.microseconds.begin(), features.folder.microseconds.end(),
                       0.0) +
       microsecondsSince(predicting)) /
      static_cast<double>(run.files.size());
  addWarnings(run, classifier);
  return run;
}

void SupervisedRun::report(std::ostream& out) const {
  std::size_t correct = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    correct += true_labels[i] == predicted[i];
  }
  char line[200];
  std::snprintf(line, sizeof(line),
                "%s: %zu objects in %.2f s, %.0f us per object on one core, accuracy %.3f\n",
                supervisedMethodName(method), files.size(), seconds, microseconds_per_object,
                files.empty() ? 0.0 : static_cast<double>(correct) / files.size());
  out << line;
  if (registration_seconds > 0.0) {
    std::snprintf(line, sizeof(line),
                  "  (after the %.2f s of registration its features came from)\n",
                  registration_seconds);
    out << line;
  }
}

TrainingRun trainOnFolder(const std::filesystem::path& folder, SupervisedMethod method,
                          const SupervisedConfig& config, int threads,
                          const std::function<void(std::size_t, std::size_t)>& progress,
                          const std::vector<std::string>& classes) {
  FolderFeatures features =
      computeFolderFeatures(folder, featureKindOf(method), config.histograms, threads, progress);
  keepClasses(features, classes, folder.string());
  TrainingSummary summary;
  SupervisedClassifier classifier =
      SupervisedClassifier::train(method, config, features.features, features.labels, &summary);
  return {std::move(classifier), summary};
}

void TrainingRun::report(std::ostream& out) const {
  char line[240];
  std::snprintf(line, sizeof(line), "%s: trained on %zu objects of %zu classes in %.2f s",
                supervisedMethodName(classifier.method()), summary.objects,
                classifier.labels().size(), summary.seconds);
  out << line;
  if (classifier.method() != SupervisedMethod::kKnn) {
    std::snprintf(line, sizeof(line),
                  "; nu %.3g, gamma %.3g (%zu pairs tried, cross-validated accuracy %.3f on "
                  "%zu objects)",
                  summary.nu, summary.gamma, summary.grid_points, summary.cross_validation,
                  summary.search_objects);
    out << line;
  }
  if (classifier.method() == SupervisedMethod::kSvmFitness) {
    if (classifier.takesPointHistograms()) {
      std::snprintf(line, sizeof(line),
                    "; on the fitness and the objects' point histograms (weight %g)",
                    classifier.config().svm_fitness.histogram_weight);
      out << line;
    } else {
      out << "; on the fitness alone";
    }
  }
  out << '\n';
}

void writeSupervisedJson(const fs::path& file, const SupervisedRun& run,
                         const SupervisedClassifier& classifier) {
  nlohmann::json objects = nlohmann::json::array();
  std::size_t labelled = 0, correct = 0;
  for (std::size_t i = 0; i < run.files.size(); ++i) {
    const bool has_label = !run.true_labels[i].empty();
    labelled += has_label;
    correct += has_label && run.true_labels[i] == run.predicted[i];
    objects.push_back({{"file", run.files[i]},
                       {"true_label", has_label ? nlohmann::json(run.true_labels[i])
                                                : nlohmann::json(nullptr)},
                       {"points", run.points[i]},
                       {"predictions", {{"label", run.predicted[i]}}}});
  }
  const TrainingSummary& training = classifier.training();
  const nlohmann::json document = {
      {"method", supervisedMethodName(run.method)},
      {"primary", "label"},
      {"features", featureKindName(featureKindOf(run.method))},
      {"labels", classifier.labels()},
      {"seconds", run.seconds},
      {"seconds_to_train", training.seconds},
      {"microseconds_per_object", run.microseconds_per_object},
      {"registration_seconds", run.registration_seconds},
      {"training",
       {{"objects", training.objects},
        {"nu", training.nu},
        {"gamma", training.gamma},
        {"cross_validation", training.cross_validation},
        {"grid_points", training.grid_points},
        {"search_objects", training.search_objects}}},
      {"objects", objects},
      {"accuracy", labelled > 0 ? static_cast<double>(correct) / labelled : 0.0},
      {"warnings", run.warnings}};

  writeFileAtomically(file, document.dump(1) + "\n", "JSON");
}

std::string trainingInputsProblem(SupervisedMethod method, const SupervisedConfig& config,
                                  bool objects, bool registration) {
  const bool from_registration = method == SupervisedMethod::kSvmFitness;
  if (from_registration && !registration) {
    return "--method svm_fitness learns from --registration results files (and the --objects "
           "they are of)";
  }
  if (!from_registration && (!objects || registration)) {
    return std::string("--method ") + supervisedMethodName(method) +
           " needs --objects (only svm_fitness takes --registration)";
  }
  if (from_registration && config.svm_fitness.histogram_weight > 0.0 && !objects) {
    return "--method svm_fitness also learns the objects' point histograms: give --objects, the "
           "folder the --registration results are of (or svm_fitness.histogram_weight: 0)";
  }
  return "";
}

std::string supervisedInputsProblem(const SupervisedClassifier& classifier,
                                    const std::string& model, const SupervisedConfig* expected,
                                    const std::string& expected_file, bool objects,
                                    bool registration) {
  if (expected != nullptr) {
    // svm_fitness's point histograms, when it takes them, are computed as the svm's.
    const std::string difference = featureConfigDifference(
        classifier.takesPointHistograms() ? SupervisedMethod::kSvm : classifier.method(),
        classifier.config().histograms, expected->histograms);
    if (!difference.empty()) {
      return model + " was trained with other feature settings than " + expected_file +
             " (histograms." + difference +
             "); retrain it, or leave --config out to use the model's own";
    }
  }
  const bool from_registration = classifier.method() == SupervisedMethod::kSvmFitness;
  if (from_registration != registration) {
    return model + " is a " + supervisedMethodName(classifier.method()) + " classifier: give it " +
           (from_registration ? "--registration results files" : "--objects, not --registration");
  }
  if (from_registration && classifier.takesPointHistograms() && !objects) {
    return model +
           " also takes the objects' point histograms: give --objects, the folder its "
           "--registration results are of";
  }
  return "";
}

}  // namespace granular
