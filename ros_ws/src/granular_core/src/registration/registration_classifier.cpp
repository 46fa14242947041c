#include "granular_core/registration/registration_classifier.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "granular_core/parallel.h"

namespace granular {
namespace {

// The cells of each model's fitness lower bound, and how far beyond its box they reach (m).
// Tuned ICP on the demo's N10 set (20,412 pairs): 0.2 m cells 0.5 m beyond reject 12,482
// fitness scores, and the seven models' cells take 48 ms of one core to build; 0.1 m cells
// (0.3 m beyond) 12,989; 0.3 m cells 12,019; 1 m beyond instead of 0.5 m
// 12,471 (the model's box bounds as well there).
constexpr float kFitnessBoundCell = 0.2f;
constexpr float kFitnessBoundMargin = 0.5f;

// The two lowest of the values offered.
struct LowestTwo {
  double first = std::numeric_limits<double>::infinity();
  double second = std::numeric_limits<double>::infinity();
  void offer(double value) {
    if (value < first) {
      second = first;
      first = value;
    } else if (value < second) {
      second = value;
    }
  }
};

// One thread's buffers for scoring an object's fitness against every model.
struct FitnessScratch {
  std::vector<ModelCloud> moved;
  std::vector<float> squared_distances;
  std::vector<double> lower_bound;
  std::vector<std::size_t> order;
};

// Scores the fitness, and the inlier shares from the same distances, of the pairs in `result`
// that registered (`registered`), each against its model's tree; with `early_rejection`, as
// RegisterOptions::early_rejection says.
void scoreFitness(const ModelCloud& source, const std::vector<NearestTree::Ptr>& trees,
                  const std::vector<bool>& registered, bool early_rejection,
                  std::vector<PairResult>& result, FitnessScratch& scratch) {
  const std::size_t models = result.size();
  scratch.moved.resize(models);
  const auto score = [&](std::size_t m) {
    result[m].fitness = trees[m]->fitnessOfMoved(scratch.moved[m], scratch.squared_distances);
    result[m].inlier_shares = inlierShares(scratch.squared_distances);
  };
  if (!early_rejection) {
    for (std::size_t m = 0; m < models; ++m) {
      if (registered[m]) {
        NearestTree::moveForFitness(source, result[m].transform, scratch.moved[m]);
        score(m);
      }
    }
    return;
  }
  scratch.lower_bound.assign(models, 0.0);
  scratch.order.clear();
  for (std::size_t m = 0; m < models; ++m) {
    if (registered[m]) {
      NearestTree::moveForFitness(source, result[m].transform, scratch.moved[m]);
      scratch.lower_bound[m] = trees[m]->fitnessLowerBound(scratch.moved[m]);
      scratch.order.push_back(m);
    }
  }
  // The likeliest winners first, so that the thresholds fall early.
  std::stable_sort(scratch.order.begin(), scratch.order.end(),
                   [&](std::size_t a, std::size_t b) {
                     return scratch.lower_bound[a] < scratch.lower_bound[b];
                   });
  LowestTwo converged;  // criterion 2's models
  LowestTwo any;        // criterion 3's
  for (const std::size_t m : scratch.order) {
    PairResult& pair = result[m];
    // A bound above the second lowest leaves the model third or later, and a tie with it
    // is scored (equal fitness goes to the model listed first).
    const double threshold = pair.converged() ? converged.second : any.second;
    if (scratch.lower_bound[m] > threshold) {
      pair.rejected = true;
      continue;
    }
    score(m);
    if (std::isfinite(pair.fitness)) {
      any.offer(pair.fitness);
      if (pair.converged()) {
        converged.offer(pair.fitness);
      }
    }
  }
}

}  // namespace

struct RegistrationClassifier::Impl {
  RegistrationMethod method;
  RegistrationClassifierConfig config;
  std::vector<std::string> labels;
  PreparedModels models;
  std::unique_ptr<RegistrationMethodImpl> registration;
  std::vector<std::string> warnings;
  /// The trees' fitness bounds are built by the first registerObjects that rejects early.
  std::once_flag fitness_bounds;
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
  std::optional<double> coarse_bound;
  if (method != RegistrationMethod::kNdt) {
    const IcpClassifierConfig& icp =
        method == RegistrationMethod::kIcp ? config.icp : config.icp_nl;
    bound = icp.max_correspondence_distance;
    if (icp.coarse_iterations > 0) {
      coarse_bound = icp.coarse_correspondence_distance;
    }
  }
  impl_->models.clouds.resize(models.size());
  impl_->models.trees.resize(models.size());
  impl_->models.coarse_trees.resize(coarse_bound ? models.size() : 0);
  // A model's tree, bounded when `bound` is finite.
  const auto treeOf = [](const ModelCloud::ConstPtr& cloud, double bound) {
    NearestTree::Ptr tree(new NearestTree);
    if (std::isfinite(bound)) {
      tree->setCorrespondenceBound(bound);
    }
    tree->setInputCloud(cloud);
    return tree;
  };
  parallelFor(models.size(), 0, 1, [&](std::size_t m) {
    const ModelCloud::ConstPtr cloud(new ModelCloud(std::move(models[m].cloud)));
    impl_->models.clouds[m] = cloud;
    impl_->models.trees[m] = treeOf(cloud, bound);
    if (coarse_bound) {
      impl_->models.coarse_trees[m] = treeOf(cloud, *coarse_bound);
    }
  });
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

void RegistrationClassifier::prepareEarlyRejection() const {
  // An exception leaves the flag unset: the next call tries again.
  std::call_once(impl_->fitness_bounds, [this] {
    parallelFor(impl_->models.trees.size(), 0, 1, [this](std::size_t m) {
      impl_->models.trees[m]->buildFitnessBound(kFitnessBoundCell, kFitnessBoundMargin);
    });
  });
}

std::vector<std::vector<PairResult>> RegistrationClassifier::registerObjects(
    const std::vector<ModelCloud>& objects, const RegisterOptions& options) const {
  if (options.early_rejection) {
    prepareEarlyRejection();
  }
  const Impl& impl = *impl_;
  const std::size_t models = impl.labels.size();
  std::vector<std::vector<PairResult>> results(objects.size());
  // Each thread's own registration objects (building them costs no tree or cell) and scratch.
  struct ThreadState {
    std::unique_ptr<ModelAligner> aligner;
    FitnessScratch scratch;
    std::vector<bool> registered;
  };
  const int threads = registrationThreads(options);
  std::vector<ThreadState> states(static_cast<std::size_t>(threads));
  // Objects differ a hundredfold in size: small dynamic chunks keep the threads even.
  parallelFor(
      objects.size(), threads, 4,
      [&](std::size_t i) {
        ThreadState& state = states[static_cast<std::size_t>(threadIndex())];
        if (!state.aligner) {
          state.aligner = impl.registration->aligner();
        }
        const ModelCloud::ConstPtr source =
            registrationSource(objects[i], impl.config);
        std::vector<PairResult>& result = results[i];
        result.assign(models, PairResult());
        if (source->size() < minimumSourcePoints(impl.method)) {
          return;
        }
        state.registered.assign(models, false);
        for (std::size_t m = 0; m < models; ++m) {
          try {
            result[m] = state.aligner->align(source, m);
            state.registered[m] = true;
          } catch (const std::exception&) {
            result[m] = failedPair();
          }
        }
        scoreFitness(*source, impl.models.trees, state.registered, options.early_rejection,
                     result, state.scratch);
      },
      options.progress);
  return results;
}

}  // namespace granular
