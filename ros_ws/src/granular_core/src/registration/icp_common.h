// What PCL's ICP and ICP-NL classes need to be reused and read as the report ran them
// (reference.cpp, the report's loop), and the states they end in, which point_to_point_icp.h's
// loop (icp.cpp, icp_nl.cpp) shares.
#pragma once

#include <memory>
#include <vector>

#include <pcl/registration/default_convergence_criteria.h>

#include "granular_core/registration/registration.h"

namespace granular {
namespace icp_detail {

using Criteria = pcl::registration::DefaultConvergenceCriteria<float>;

// PCL's ICP or ICP-NL with the iteration count it keeps protected (PCL 1.13's member;
// test_pcl_internals.cpp says so on an upgrade).
template <typename Base>
class IcpWithIterations : public Base {
 public:
  int iterations() const { return this->nr_iterations_; }
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

// Aligns `source` with a registration object whose target is set, from `guess`, with PCL's
// getFitnessScore(); `aligned` is scratch.
template <typename Registration>
PairResult alignIcp(Registration& icp, const ModelCloud::ConstPtr& source, ModelCloud& aligned,
                    const Eigen::Matrix4f& guess = Eigen::Matrix4f::Identity()) {
  icp.setInputSource(source);
  icp.align(aligned, guess);
  PairResult result;
  result.state = icpState(icp.getConvergeCriteria()->getConvergenceState());
  result.iterations = icp.iterations();
  result.transform = icp.getFinalTransformation();
  result.fitness = icp.getFitnessScore();
  return result;
}

}  // namespace icp_detail
}  // namespace granular
