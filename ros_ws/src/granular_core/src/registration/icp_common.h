// ICP and ICP-NL share everything but PCL's class: icp.cpp and icp_nl.cpp each instantiate
// one of them (PCL's registration templates compile slowly; one per translation unit), and
// reference.cpp both, for the report's loop.
#pragma once

#include <memory>
#include <vector>

#include <pcl/registration/default_convergence_criteria.h>

#include "granular_core/registration/registration.h"

namespace granular {
namespace icp_detail {

using Criteria = pcl::registration::DefaultConvergenceCriteria<float>;

// PCL's ICP or ICP-NL with the two things PCL keeps protected that a reused object needs
// (PCL 1.13's members; test_pcl_internals.cpp says so on an upgrade).
template <typename Base>
class ReusableIcp : public Base {
 public:
  int iterations() const { return this->nr_iterations_; }

  // DefaultConvergenceCriteria keeps the previous run's mean squared error (and state) across
  // align() calls, so the first iteration of the next object would compare against it; a
  // fresh criteria object makes a reused ICP behave exactly like a new one.
  void resetConvergenceCriteria() {
    this->convergence_criteria_.reset(
        new Criteria(this->nr_iterations_, this->transformation_, *this->correspondences_));
  }
};

template <typename Registration>
void configure(Registration& icp, const IcpClassifierConfig& config) {
  icp.setMaximumIterations(config.max_iterations);
  icp.setMaxCorrespondenceDistance(config.max_correspondence_distance);
  icp.setTransformationEpsilon(config.transformation_epsilon);
  icp.setEuclideanFitnessEpsilon(config.euclidean_fitness_epsilon);
}

inline RegistrationState icpState(Criteria::ConvergenceState state) {
  switch (state) {
    case Criteria::CONVERGENCE_CRITERIA_TRANSFORM:
      return RegistrationState::kTransform;
    case Criteria::CONVERGENCE_CRITERIA_ABS_MSE:
      return RegistrationState::kAbsMse;
    case Criteria::CONVERGENCE_CRITERIA_REL_MSE:
      return RegistrationState::kRelMse;
    case Criteria::CONVERGENCE_CRITERIA_ITERATIONS:
    case Criteria::CONVERGENCE_CRITERIA_FAILURE_AFTER_MAX_ITERATIONS:
      return RegistrationState::kIterations;
    case Criteria::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES:
      return RegistrationState::kNoCorrespondences;
    case Criteria::CONVERGENCE_CRITERIA_NOT_CONVERGED:
      break;
  }
  return RegistrationState::kFailed;
}

// Aligns `source` with a registration object whose target is set; `aligned` is scratch.
// `tree`: the target's NearestTree, for the fitness; nullptr uses PCL's getFitnessScore().
template <typename Registration>
PairResult alignIcp(Registration& icp, const ModelCloud::ConstPtr& source, ModelCloud& aligned,
                    const NearestTree* tree) {
  icp.setInputSource(source);
  icp.align(aligned);
  PairResult result;
  result.state = icpState(icp.getConvergeCriteria()->getConvergenceState());
  result.iterations = icp.iterations();
  result.transform = icp.getFinalTransformation();
  result.fitness = tree != nullptr ? tree->fitness(*source, result.transform)
                                   : icp.getFitnessScore();
  return result;
}

// One thread's ICP objects, one per model, sharing the models' prebuilt trees.
template <typename Registration>
class IcpAligner : public ModelAligner {
 public:
  IcpAligner(const IcpClassifierConfig& config, const PreparedModels& models)
      : models_(models) {
    for (std::size_t m = 0; m < models.clouds.size(); ++m) {
      auto icp = std::make_unique<Registration>();
      configure(*icp, config);
      icp->setInputTarget(models.clouds[m]);
      // true: never rebuild the tree (it is shared, and already built on this target).
      icp->setSearchMethodTarget(models.trees[m], true);
      icps_.push_back(std::move(icp));
    }
  }

  PairResult align(const ModelCloud::ConstPtr& source, std::size_t model) override {
    icps_[model]->resetConvergenceCriteria();
    return alignIcp(*icps_[model], source, aligned_, models_.trees[model].get());
  }

 private:
  const PreparedModels& models_;
  std::vector<std::unique_ptr<Registration>> icps_;
  ModelCloud aligned_;
};

template <typename Registration>
class IcpMethod : public RegistrationMethodImpl {
 public:
  IcpMethod(const IcpClassifierConfig& config, const PreparedModels& models)
      : config_(config), models_(models) {
    for (const NearestTree::Ptr& tree : models.trees) {
      tree->setCorrespondenceBound(config.max_correspondence_distance);
    }
  }

  std::unique_ptr<ModelAligner> aligner() const override {
    return std::make_unique<IcpAligner<Registration>>(config_, models_);
  }

 private:
  IcpClassifierConfig config_;
  const PreparedModels& models_;
};

}  // namespace icp_detail
}  // namespace granular
