// The only translation unit that instantiates pcl::IterativeClosestPoint (header-only in PCL):
// keep every use of it here, it takes long to compile.
#include "granular_core/models/icp_concatenate.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <pcl/registration/icp.h>

#include "granular_core/models/filter_chain.h"

namespace granular {
namespace {

using Icp = pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ, float>;
using Criteria = pcl::registration::DefaultConvergenceCriteria<float>;

IcpConvergence fromPcl(Criteria::ConvergenceState state) {
  switch (state) {
    case Criteria::CONVERGENCE_CRITERIA_NOT_CONVERGED:
      return IcpConvergence::kNotConverged;
    case Criteria::CONVERGENCE_CRITERIA_ITERATIONS:
      return IcpConvergence::kIterations;
    case Criteria::CONVERGENCE_CRITERIA_TRANSFORM:
      return IcpConvergence::kTransform;
    case Criteria::CONVERGENCE_CRITERIA_ABS_MSE:
      return IcpConvergence::kAbsMse;
    case Criteria::CONVERGENCE_CRITERIA_REL_MSE:
      return IcpConvergence::kRelMse;
    case Criteria::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES:
      return IcpConvergence::kNoCorrespondences;
    case Criteria::CONVERGENCE_CRITERIA_FAILURE_AFTER_MAX_ITERATIONS:
      return IcpConvergence::kFailureAfterMaxIterations;
  }
  return IcpConvergence::kNotConverged;
}

// One ICP set up once; the target's search tree is rebuilt only when the target changes.
class Aligner {
 public:
  explicit Aligner(const IcpConfig& config) : config_(config) {
    icp_.setMaximumIterations(config.max_iterations);
    icp_.setMaxCorrespondenceDistance(config.max_correspondence_distance);
    icp_.setTransformationEpsilon(config.transformation_epsilon);
    icp_.setEuclideanFitnessEpsilon(config.euclidean_fitness_epsilon);
  }

  void setTarget(ModelCloud::ConstPtr target) {
    target_ = std::move(target);
    icp_.setInputTarget(target_);
  }

  Alignment align(const ModelCloud& object, ModelCloud* aligned) {
    Alignment result;
    result.fitness = std::numeric_limits<double>::quiet_NaN();
    if (object.size() < config_.min_points) {
      result.verdict = IcpVerdict::kTooFewPoints;
      return result;
    }
    if (target_->empty()) {
      result.verdict = IcpVerdict::kNotConverged;
      result.convergence = IcpConvergence::kNoCorrespondences;
      return result;
    }
    icp_.setInputSource(ModelCloud::ConstPtr(new ModelCloud(object)));
    ModelCloud moved;
    icp_.align(moved);
    // Not icp_.hasConverged(): it is also true when ICP only ran out of iterations.
    result.convergence = fromPcl(icp_.getConvergeCriteria()->getConvergenceState());
    result.transform = icp_.getFinalTransformation();
    result.fitness = icp_.getFitnessScore();
    result.translation = result.transform.block<3, 1>(0, 3).cast<double>().norm();
    const double cosine = (result.transform.block<3, 3>(0, 0).trace() - 1.0) / 2.0;
    result.rotation_deg = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI;

    if (!isConverged(result.convergence)) {
      result.verdict = IcpVerdict::kNotConverged;
    } else if (!(result.fitness <= config_.max_fitness)) {
      result.verdict = IcpVerdict::kPoorFitness;
    } else if (result.translation > config_.max_translation ||
               result.rotation_deg > config_.max_rotation_deg) {
      result.verdict = IcpVerdict::kLargeCorrection;
    } else {
      result.verdict = IcpVerdict::kKept;
    }
    if (aligned != nullptr) {
      *aligned = std::move(moved);
    }
    return result;
  }

 private:
  IcpConfig config_;
  Icp icp_;
  ModelCloud::ConstPtr target_{new ModelCloud};
};

}  // namespace

const char* convergenceName(IcpConvergence convergence) {
  switch (convergence) {
    case IcpConvergence::kNotConverged:
      return "not_converged";
    case IcpConvergence::kIterations:
      return "iterations";
    case IcpConvergence::kTransform:
      return "transform";
    case IcpConvergence::kAbsMse:
      return "abs_mse";
    case IcpConvergence::kRelMse:
      return "rel_mse";
    case IcpConvergence::kNoCorrespondences:
      return "no_correspondences";
    case IcpConvergence::kFailureAfterMaxIterations:
      return "failure_after_max_iterations";
  }
  return "unknown";
}

bool isConverged(IcpConvergence convergence) {
  return convergence == IcpConvergence::kTransform || convergence == IcpConvergence::kAbsMse ||
         convergence == IcpConvergence::kRelMse;
}

const char* verdictName(IcpVerdict verdict) {
  switch (verdict) {
    case IcpVerdict::kKept:
      return "kept";
    case IcpVerdict::kTooFewPoints:
      return "too_few_points";
    case IcpVerdict::kNotConverged:
      return "not_converged";
    case IcpVerdict::kPoorFitness:
      return "poor_fitness";
    case IcpVerdict::kLargeCorrection:
      return "large_correction";
  }
  return "unknown";
}

Alignment alignToModel(const ModelCloud& object, const ModelCloud& target,
                       const IcpConfig& config, ModelCloud* aligned) {
  Aligner aligner(config);
  aligner.setTarget(ModelCloud::ConstPtr(new ModelCloud(target)));
  return aligner.align(object, aligned);
}

IcpConcatenation concatenateWithIcp(const std::vector<ModelCloud>& objects,
                                    const ModelCloud& seed,
                                    const std::vector<std::size_t>& seed_objects,
                                    const IcpConfig& config,
                                    const std::function<void(std::size_t, std::size_t)>& progress) {
  IcpConcatenation result;
  result.model = seed;
  result.alignments.resize(objects.size());
  std::vector<bool> in_seed(objects.size(), false);
  for (const std::size_t index : seed_objects) {
    if (index < objects.size() && !in_seed[index]) {
      in_seed[index] = true;
      result.alignments[index].verdict = IcpVerdict::kKept;
      ++result.kept;
    }
  }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (!in_seed[i]) {
      order.push_back(i);
    }
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return objects[a].size() > objects[b].size();
  });

  Aligner aligner(config);
  const auto refresh_target = [&]() {
    aligner.setTarget(ModelCloud::ConstPtr(new ModelCloud(
        config.target_leaf_size > 0.0 ? voxelGrid(result.model, {config.target_leaf_size})
                                      : result.model)));
  };
  refresh_target();
  for (std::size_t done = 0; done < order.size(); ++done) {
    const std::size_t index = order[done];
    ModelCloud aligned;
    result.alignments[index] = aligner.align(objects[index], &aligned);
    if (result.alignments[index].verdict == IcpVerdict::kKept) {
      result.model += aligned;
      ++result.kept;
      refresh_target();
    }
    if (progress) {
      progress(done + 1, order.size());
    }
  }
  return result;
}

}  // namespace granular
