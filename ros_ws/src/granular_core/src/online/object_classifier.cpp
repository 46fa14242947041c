#include "granular_core/online/object_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/models_folder.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/parallel.h"
#include "granular_core/registration/criteria.h"

namespace granular {
namespace {

// 1 - best / second best fitness among the eligible models; 1 with a single eligible model.
template <typename Eligible>
double fitnessMargin(const std::vector<PairResult>& per_model, std::size_t best,
                     Eligible eligible) {
  double second = std::numeric_limits<double>::infinity();
  for (std::size_t m = 0; m < per_model.size(); ++m) {
    if (m != best && eligible(per_model[m])) {
      second = std::min(second, per_model[m].fitness);
    }
  }
  if (!std::isfinite(second) || second <= 0.0) {
    return 1.0;
  }
  return std::clamp(1.0 - per_model[best].fitness / second, 0.0, 1.0);
}

// The supervised classifier's answers for the objects `classified` names (indices into
// `objects`), from featuresOf(i), each object's features computed on its own and spread over
// the frame's threads, as registration is. The objects with the most points go first, one at
// a time: an object's point histograms cost grows with its points (a 1,500-point car costs 50
// small ones), and one handed out last would keep a thread busy while the others idle.
template <typename FeaturesOf>
void predictLargestFirst(const SupervisedClassifier& classifier, const std::vector<Cloud>& objects,
                         const std::vector<std::size_t>& classified, int threads,
                         FeaturesOf featuresOf, std::vector<ObjectPrediction>& predictions) {
  std::vector<std::size_t> order(classified.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return objects[classified[a]].size() > objects[classified[b]].size();
  });
  std::vector<std::vector<float>> features(classified.size());
  parallelFor(order.size(), threads, 1, [&](std::size_t position) {
    const std::size_t k = order[position];
    features[k] = featuresOf(classified[k]);
  });
  const std::vector<SupervisedPrediction> answers = classifier.predictWithScores(features);
  for (std::size_t k = 0; k < classified.size(); ++k) {
    predictions[classified[k]] = {true, answers[k].label, answers[k].score};
  }
}

}  // namespace

struct ObjectClassifier::Impl {
  std::optional<RegistrationClassifier> registration;
  std::optional<SupervisedClassifier> supervised;
  /// svm_fitness: one registration per results file it learnt from, in their order.
  std::vector<RegistrationClassifier> fitness_registrations;
  int threads = 1;
  std::vector<std::string> warnings;
};

ObjectClassifier::ObjectClassifier() : impl_(std::make_unique<Impl>()) {}
ObjectClassifier::ObjectClassifier(ObjectClassifier&&) noexcept = default;
ObjectClassifier& ObjectClassifier::operator=(ObjectClassifier&&) noexcept = default;
ObjectClassifier::~ObjectClassifier() = default;

ObjectClassifier ObjectClassifier::registration(RegistrationMethod method,
                                                const RegistrationClassifierConfig& config,
                                                const std::filesystem::path& models,
                                                int threads) {
  ObjectClassifier classifier;
  classifier.impl_->registration.emplace(method, config, readClassModels(models));
  classifier.impl_->registration->prepareEarlyRejection();  // before the first frame
  classifier.impl_->threads = threads;
  classifier.impl_->warnings = classifier.impl_->registration->warnings();
  return classifier;
}

ObjectClassifier ObjectClassifier::supervised(const std::filesystem::path& file, int threads) {
  ObjectClassifier classifier;
  classifier.impl_->supervised.emplace(SupervisedClassifier::load(file));
  if (classifier.impl_->supervised->method() == SupervisedMethod::kSvmFitness) {
    // Its features need every object registered against every model by each of its methods.
    throw std::invalid_argument(file.string() +
                                ": svm_fitness needs the class models it learnt from as well "
                                "(ObjectClassifier::fitness; online.launch class_models:=)");
  }
  classifier.impl_->threads = threads;
  return classifier;
}

ObjectClassifier ObjectClassifier::fitness(
    const std::filesystem::path& file, const std::filesystem::path& models,
    const std::function<RegistrationClassifierConfig(const std::string&)>& preset, int threads) {
  ObjectClassifier classifier;
  classifier.impl_->supervised.emplace(SupervisedClassifier::load(file));
  const SupervisedClassifier& svm = *classifier.impl_->supervised;
  if (svm.method() != SupervisedMethod::kSvmFitness) {
    throw std::invalid_argument(file.string() + " holds a " + supervisedMethodName(svm.method()) +
                                " classifier, not svm_fitness");
  }
  const std::vector<LabelledModel> clouds = readClassModels(models);
  std::vector<std::string> labels;
  for (const LabelledModel& model : clouds) {
    labels.push_back(model.label);
  }
  for (const nlohmann::json& source : nlohmann::json::parse(svm.featureOrigin().source)) {
    const std::string name = source.at("method").get<std::string>();
    const std::optional<RegistrationMethod> method = registrationMethodFromName(name);
    if (!method) {
      throw std::invalid_argument(file.string() + ": unknown registration method '" + name + "'");
    }
    const std::string preset_name = source.at("preset").get<std::string>();
    const RegistrationClassifierConfig config = preset(preset_name);
    const nlohmann::json parameters = registrationParameters(*method, config);
    if (parameters != source.at("parameters")) {
      throw std::invalid_argument(file.string() + " learnt from " + name + " with " +
                                  source.at("parameters").dump() + "; preset '" + preset_name +
                                  "' gives " + parameters.dump());
    }
    if (source.at("models").get<std::vector<std::string>>() != labels) {
      throw std::invalid_argument(file.string() + " learnt from the models " +
                                  source.at("models").dump() + "; " + models.string() +
                                  " holds " + nlohmann::json(labels).dump());
    }
    classifier.impl_->fitness_registrations.emplace_back(*method, config, clouds);
    for (const std::string& warning : classifier.impl_->fitness_registrations.back().warnings()) {
      classifier.impl_->warnings.push_back(warning);
    }
  }
  classifier.impl_->threads = threads;
  return classifier;
}

std::string ObjectClassifier::method() const {
  return impl_->registration ? registrationMethodName(impl_->registration->method())
                             : supervisedMethodName(impl_->supervised->method());
}

std::vector<std::string> ObjectClassifier::labels() const {
  return impl_->registration ? impl_->registration->labels() : impl_->supervised->labels();
}

const std::vector<std::string>& ObjectClassifier::warnings() const { return impl_->warnings; }

std::vector<ObjectPrediction> ObjectClassifier::classify(const std::vector<Cloud>& objects) const {
  std::vector<ObjectPrediction> predictions(objects.size());
  RegisterOptions options;
  options.threads = impl_->threads;
  if (!impl_->fitness_registrations.empty()) {
    std::vector<ModelCloud> clouds;
    for (const Cloud& object : objects) {
      clouds.push_back(toModelCloud(object));
    }
    // pairs[object][method][model], as classify_registration's results record them.
    std::vector<std::vector<std::vector<PairFitness>>> pairs(objects.size());
    for (const RegistrationClassifier& registration : impl_->fitness_registrations) {
      const std::vector<std::vector<PairResult>> results =
          registration.registerObjects(clouds, options);
      for (std::size_t i = 0; i < objects.size(); ++i) {
        std::vector<PairFitness>& per_model = pairs[i].emplace_back();
        for (const PairResult& result : results[i]) {
          const std::optional<double> fitness = result.reportedFitness();
          per_model.push_back({fitness, fitness ? result.inlier_shares : InlierShares{}});
        }
      }
    }
    std::vector<std::size_t> classified;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (!clouds[i].empty()) {
        classified.push_back(i);
      }
    }
    // With the objects' point histograms when the classifier takes them.
    const SupervisedClassifier& classifier = *impl_->supervised;
    predictLargestFirst(classifier, objects, classified, impl_->threads, [&](std::size_t i) {
      return classifier.fitnessFeatures(
          registrationFitnessFeatures(pairs[i], clouds[i].size(), classifier.takesInlierShares()),
          objects[i]);
    }, predictions);
    return predictions;
  }
  if (impl_->supervised) {
    const SupervisedClassifier& classifier = *impl_->supervised;
    std::vector<std::size_t> classified;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (!objects[i].empty()) {
        classified.push_back(i);
      }
    }
    predictLargestFirst(classifier, objects, classified, impl_->threads,
                        [&](std::size_t i) { return classifier.features(objects[i]); },
                        predictions);
    return predictions;
  }
  const RegistrationClassifier& classifier = *impl_->registration;
  // The label and its margin read only the best and second best fitness.
  options.early_rejection = true;
  std::vector<ModelCloud> clouds;
  clouds.reserve(objects.size());
  for (const Cloud& object : objects) {
    clouds.push_back(toModelCloud(object));
  }
  const std::vector<std::vector<PairResult>> results = classifier.registerObjects(clouds, options);
  const std::vector<std::string> labels = classifier.labels();
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const Predictions criteria = predict(results[i]);
    if (criteria.criterion2) {
      predictions[i] = {true, labels[*criteria.criterion2],
                        fitnessMargin(results[i], *criteria.criterion2,
                                      [](const PairResult& r) { return r.converged(); })};
    } else if (criteria.criterion3) {
      predictions[i] = {true, labels[*criteria.criterion3],
                        fitnessMargin(results[i], *criteria.criterion3,
                                      [](const PairResult& r) { return r.ran(); })};
    }
  }
  return predictions;
}

}  // namespace granular
