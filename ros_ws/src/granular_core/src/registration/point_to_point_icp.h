// The loop of PCL 1.13's IterativeClosestPoint::computeTransformation, which ICP and ICP-NL
// share (they differ in the step that estimates each iteration's transform), written out for
// one model and reused object after object. It does PCL's arithmetic step for step (the same
// correspondences in the same order, the same transform of the points, PCL's own convergence
// criteria), so iterations, states and transforms are PCL's bit for bit: the registration
// gtest and bench_registration compare it with PCL's class. What it leaves out is what PCL's
// class spends besides: per iteration a copy of the correspondences, two vectors per
// nearest-point query and iterators over the pairs; per object a copy of the source.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include <pcl/common/eigen.h>
#include <pcl/correspondence.h>

#include "granular_core/registration/point_to_point_lm.h"
#include "icp_common.h"

namespace granular {
namespace icp_detail {

// PCL's TransformationEstimationSVD (Umeyama, float) on the pairs, in their order.
class SvdStep {
 public:
  static constexpr std::size_t kMinimumPairs = 3;  // PCL's ICP refuses fewer

  void operator()(const ModelCloud& source, const ModelCloud& target,
                  const pcl::Correspondences& pairs, Eigen::Matrix4f& transformation) {
    const auto count = static_cast<Eigen::Index>(pairs.size());
    from_.resize(3, count);
    to_.resize(3, count);
    for (Eigen::Index i = 0; i < count; ++i) {
      const pcl::PointXYZ& from = source[pairs[i].index_query];
      const pcl::PointXYZ& to = target[pairs[i].index_match];
      from_.col(i) << from.x, from.y, from.z;
      to_.col(i) << to.x, to.y, to.z;
    }
    transformation = pcl::umeyama(from_, to_, false);
  }

 private:
  Eigen::Matrix<float, 3, Eigen::Dynamic> from_, to_;
};

// ICP-NL's step: pointToPointLm (analytic Jacobians, double), which minimises the sum PCL's
// TransformationEstimationLM minimises with numerical ones.
class AnalyticLmStep {
 public:
  static constexpr std::size_t kMinimumPairs = 4;  // PCL's ICP-NL refuses fewer

  void operator()(const ModelCloud& source, const ModelCloud& target,
                  const pcl::Correspondences& pairs, Eigen::Matrix4f& transformation) {
    from_.clear();
    to_.clear();
    for (const pcl::Correspondence& pair : pairs) {
      const pcl::PointXYZ& from = source[pair.index_query];
      const pcl::PointXYZ& to = target[pair.index_match];
      from_.emplace_back(from.x, from.y, from.z);
      to_.emplace_back(to.x, to.y, to.z);
    }
    transformation = pointToPointLm(from_, to_).matrix().cast<float>();
  }

 private:
  std::vector<Eigen::Vector3d> from_, to_;
};

// IterativeClosestPoint::transformCloud for x y z points, in place.
inline void transformInPlace(ModelCloud& cloud, const Eigen::Matrix4f& transform) {
  Eigen::Vector4f point(0.0f, 0.0f, 0.0f, 1.0f);
  for (pcl::PointXYZ& p : cloud) {
    point[0] = p.x;
    point[1] = p.y;
    point[2] = p.z;
    if (!std::isfinite(point[0]) || !std::isfinite(point[1]) || !std::isfinite(point[2])) {
      continue;
    }
    const Eigen::Vector4f moved = transform * point;
    p.x = moved[0];
    p.y = moved[1];
    p.z = moved[2];
  }
}

// One thread's registrations against every model, reusing its buffers.
template <typename Step>
class PointToPointAligner : public ModelAligner {
 public:
  PointToPointAligner(const IcpClassifierConfig& config, const PreparedModels& models)
      : config_(config), models_(models) {}

  PairResult align(const ModelCloud::ConstPtr& source, std::size_t model) override {
    const ModelCloud& target = *models_.clouds[model];
    int iterations = 0;
    Eigen::Matrix4f total = Eigen::Matrix4f::Identity();
    if (config_.coarse_iterations > 0) {
      moved_ = *source;
      runStage(target, *models_.coarse_trees[model], config_.coarse_correspondence_distance,
               config_.coarse_iterations, total, iterations);
    }
    // As PCL's second registration given the coarse transform as its guess: the source moved
    // by it in one go (an identity guess leaves it as it is), then the same loop.
    moved_ = *source;
    if (total != Eigen::Matrix4f::Identity()) {
      transformInPlace(moved_, total);
    }
    PairResult result;
    result.state = icpState(runStage(target, *models_.trees[model],
                                     config_.max_correspondence_distance,
                                     config_.max_iterations, total, iterations));
    result.iterations = iterations;
    result.transform = total;
    return result;
  }

 private:
  // PCL's loop on moved_, pairing points up to `max_distance` with `tree` (bounded by it), for
  // at most `max_iterations` iterations; each step is applied to moved_ and `total`, and
  // counted in `iterations`. Returns the state that ended it.
  Criteria::ConvergenceState runStage(const ModelCloud& target, const NearestTree& tree,
                                      double max_distance, int max_iterations,
                                      Eigen::Matrix4f& total, int& iterations) {
    int stage_iterations = 0;
    Eigen::Matrix4f step = Eigen::Matrix4f::Identity();
    // A fresh criteria object per registration, as a new PCL object has.
    Criteria criteria(stage_iterations, step, pairs_);
    criteria.setMaximumIterations(max_iterations);
    criteria.setRelativeMSE(config_.euclidean_fitness_epsilon);
    criteria.setTranslationThreshold(config_.transformation_epsilon);
    criteria.setRotationThreshold(1.0 - config_.transformation_epsilon);
    const double max_squared = max_distance * max_distance;
    do {
      pairs_.clear();
      for (std::size_t i = 0; i < moved_.size(); ++i) {
        const pcl::PointXYZ& point = moved_[i];
        const NearestTree::Neighbour nearest = tree.nearestWithinBound(point);
        // PCL's test, in double: the tree finds points up to the smallest float at or above
        // max_squared, which may lie just beyond it.
        if (!nearest.found || nearest.squared > max_squared) {
          continue;
        }
        pcl::Correspondence pair;
        pair.index_query = static_cast<pcl::index_t>(i);
        pair.index_match = nearest.index;
        pair.distance = nearest.squared;
        pairs_.push_back(pair);
      }
      if (pairs_.size() < Step::kMinimumPairs) {
        criteria.setConvergenceState(Criteria::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES);
        break;
      }
      step_(moved_, target, pairs_, step);
      transformInPlace(moved_, step);
      total = step * total;
      ++stage_iterations;
      criteria.hasConverged();  // sets the state that ends the loop
    } while (criteria.getConvergenceState() == Criteria::CONVERGENCE_CRITERIA_NOT_CONVERGED);
    iterations += stage_iterations;
    return criteria.getConvergenceState();
  }

  const IcpClassifierConfig config_;
  const PreparedModels& models_;
  Step step_;
  ModelCloud moved_;
  pcl::Correspondences pairs_;
};

template <typename Step>
class PointToPointMethod : public RegistrationMethodImpl {
 public:
  // `models`' trees are bounded by config.max_correspondence_distance already, and its
  // coarse_trees by config.coarse_correspondence_distance when there is a coarse stage
  // (RegistrationClassifier sets the bounds before their clouds, so that only those grids are
  // built).
  PointToPointMethod(const IcpClassifierConfig& config, const PreparedModels& models)
      : config_(config), models_(models) {}

  std::unique_ptr<ModelAligner> aligner() const override {
    return std::make_unique<PointToPointAligner<Step>>(config_, models_);
  }

 private:
  IcpClassifierConfig config_;
  const PreparedModels& models_;
};

}  // namespace icp_detail
}  // namespace granular
