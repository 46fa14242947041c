#include "granular_core/registration/registration_classifier.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace granular {

struct RegistrationClassifier::Impl {
  RegistrationMethod method;
  RegistrationClassifierConfig config;
  std::vector<std::string> labels;
  PreparedModels models;
  std::unique_ptr<RegistrationMethodImpl> registration;
  std::vector<std::string> warnings;
};

RegistrationClassifier::RegistrationClassifier(RegistrationMethod method,
                                               const RegistrationClassifierConfig& config,
                                               std::vector<LabelledModel> models)
    : impl_(std::make_unique<Impl>()) {
  validate(config);
  if (models.empty()) {
    throw std::invalid_argument("no class models");
  }
  impl_->method = method;
  impl_->config = config;
  for (const LabelledModel& model : models) {
    if (model.label.empty()) {
      throw std::invalid_argument("a class model has an empty label");
    }
    if (std::find(impl_->labels.begin(), impl_->labels.end(), model.label) !=
        impl_->labels.end()) {
      throw std::invalid_argument("two class models are labelled '" + model.label + "'");
    }
    if (model.cloud.empty()) {
      throw std::invalid_argument("the model of class '" + model.label + "' has no points");
    }
    impl_->labels.push_back(model.label);
  }
  // The ICP methods search within their correspondence bound: each tree gets it before its
  // cloud, so that only the grid for it is built. The models are built on every core.
  double bound = std::numeric_limits<double>::infinity();
  if (method == RegistrationMethod::kIcp) {
    bound = config.icp.max_correspondence_distance;
  } else if (method == RegistrationMethod::kIcpNl) {
    bound = config.icp_nl.max_correspondence_distance;
  }
  const long count = static_cast<long>(models.size());
  impl_->models.clouds.resize(models.size());
  impl_->models.trees.resize(models.size());
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1)
  for (long m = 0; m < count; ++m) {
    try {
      const ModelCloud::ConstPtr cloud(new ModelCloud(std::move(models[m].cloud)));
      NearestTree::Ptr tree(new NearestTree);
      if (std::isfinite(bound)) {
        tree->setCorrespondenceBound(bound);
      }
      tree->setInputCloud(cloud);
      impl_->models.clouds[m] = cloud;
      impl_->models.trees[m] = tree;
    } catch (...) {
#pragma omp critical(granular_model_error)
      error = error ? error : std::current_exception();
    }
  }
  if (error) {
    std::rethrow_exception(error);
  }
  switch (method) {
    case RegistrationMethod::kIcp:
      impl_->registration = prepareIcp(config.icp, impl_->models);
      break;
    case RegistrationMethod::kIcpNl:
      impl_->registration = prepareIcpNl(config.icp_nl, impl_->models);
      break;
    case RegistrationMethod::kNdt:
      impl_->registration = prepareNdt(config.ndt, impl_->models, impl_->labels);
      break;
  }
  impl_->warnings = impl_->registration->warnings();
}

RegistrationClassifier::~RegistrationClassifier() = default;
RegistrationClassifier::RegistrationClassifier(RegistrationClassifier&&) noexcept = default;
RegistrationClassifier& RegistrationClassifier::operator=(RegistrationClassifier&&) noexcept =
    default;

RegistrationMethod RegistrationClassifier::method() const { return impl_->method; }

const RegistrationClassifierConfig& RegistrationClassifier::config() const {
  return impl_->config;
}

std::vector<std::string> RegistrationClassifier::labels() const { return impl_->labels; }

const std::vector<std::string>& RegistrationClassifier::warnings() const {
  return impl_->warnings;
}

int registrationThreads(const RegisterOptions& options) {
  if (options.threads > 0) {
    return options.threads;
  }
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

std::vector<std::vector<PairResult>> RegistrationClassifier::registerObjects(
    const std::vector<ModelCloud>& objects, const RegisterOptions& options) const {
  const Impl& impl = *impl_;
  const std::size_t models = impl.labels.size();
  std::vector<std::vector<PairResult>> results(objects.size());
  const long count = static_cast<long>(objects.size());
  std::size_t done = 0;
  std::exception_ptr error;
#pragma omp parallel num_threads(registrationThreads(options))
  {
    // Each thread's own registration objects; building them costs no tree or cell.
    std::unique_ptr<ModelAligner> aligner;
    try {
      aligner = impl.registration->aligner();
    } catch (...) {
#pragma omp critical(granular_registration_error)
      error = error ? error : std::current_exception();
    }
    // Objects differ a hundredfold in size: small dynamic chunks keep the threads even.
#pragma omp for schedule(dynamic, 4)
    for (long i = 0; i < count; ++i) {
      if (!aligner) {
        continue;
      }
      const ModelCloud::ConstPtr source =
          registrationSource(objects[static_cast<std::size_t>(i)], impl.config.source_min_z);
      std::vector<PairResult>& result = results[static_cast<std::size_t>(i)];
      result.assign(models, PairResult());
      if (source->size() >= minimumSourcePoints(impl.method)) {
        for (std::size_t m = 0; m < models; ++m) {
          try {
            result[m] = aligner->align(source, m);
          } catch (const std::exception&) {
            result[m] = failedPair();
          }
        }
      }
#pragma omp critical(granular_registration_progress)
      {
        ++done;
        if (options.progress) {
          options.progress(done, objects.size());
        }
      }
    }
  }
  if (error) {
    std::rethrow_exception(error);
  }
  return results;
}

}  // namespace granular
