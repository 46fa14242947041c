#include "granular_core/online/object_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "granular_core/runs/classify_registration_run.h"
#include "granular_core/dataset/pcd_io.h"

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

}  // namespace

struct ObjectClassifier::Impl {
  std::optional<RegistrationClassifier> registration;
  std::optional<SupervisedClassifier> supervised;
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
                                ": svm_fitness classifies registration results offline "
                                "(classify_supervised --registration); online, use one of its "
                                "registration methods or knn/svm");
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
  if (impl_->supervised) {
    const SupervisedClassifier& classifier = *impl_->supervised;
    std::vector<std::size_t> classified;
    std::vector<std::vector<float>> features;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (!objects[i].empty()) {
        classified.push_back(i);
        features.push_back(classifier.features(objects[i]));
      }
    }
    const std::vector<SupervisedPrediction> answers = classifier.predictWithScores(features);
    for (std::size_t k = 0; k < classified.size(); ++k) {
      predictions[classified[k]] = {true, answers[k].label, answers[k].score};
    }
    return predictions;
  }
  const RegistrationClassifier& classifier = *impl_->registration;
  std::vector<ModelCloud> clouds;
  clouds.reserve(objects.size());
  for (const Cloud& object : objects) {
    clouds.push_back(toModelCloud(object));
  }
  RegisterOptions options;
  options.threads = impl_->threads;
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
