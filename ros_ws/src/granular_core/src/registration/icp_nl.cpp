// report 8.2: pcl::IterativeClosestPointNonLinear, reused per model and thread, with its
// Levenberg-Marquardt step (PCL's TransformationEstimationLM: numerical Jacobians, float)
// replaced by pointToPointLm (analytic Jacobians, double) that minimises the same sum.
// reference.cpp keeps PCL's own for the report's loop.
#include <pcl/registration/icp_nl.h>
#include <pcl/registration/transformation_estimation.h>

#include "granular_core/registration/point_to_point_lm.h"
#include "icp_common.h"

namespace granular {
namespace {

using Point = pcl::PointXYZ;
using Cloud = pcl::PointCloud<Point>;

class AnalyticLmEstimation : public pcl::registration::TransformationEstimation<Point, Point> {
 public:
  void estimateRigidTransformation(const Cloud& source, const Cloud& target,
                                   Matrix4& transformation) const override {
    if (source.size() == target.size()) {
      for (std::size_t i = 0; i < source.size(); ++i) {
        add(source[i], target[i]);
      }
      solve(transformation);
    }
  }

  void estimateRigidTransformation(const Cloud& source, const pcl::Indices& source_indices,
                                   const Cloud& target, Matrix4& transformation) const override {
    if (source_indices.size() == target.size()) {
      for (std::size_t i = 0; i < source_indices.size(); ++i) {
        add(source[source_indices[i]], target[i]);
      }
      solve(transformation);
    }
  }

  void estimateRigidTransformation(const Cloud& source, const pcl::Indices& source_indices,
                                   const Cloud& target, const pcl::Indices& target_indices,
                                   Matrix4& transformation) const override {
    if (source_indices.size() == target_indices.size()) {
      for (std::size_t i = 0; i < source_indices.size(); ++i) {
        add(source[source_indices[i]], target[target_indices[i]]);
      }
      solve(transformation);
    }
  }

  void estimateRigidTransformation(const Cloud& source, const Cloud& target,
                                   const pcl::Correspondences& correspondences,
                                   Matrix4& transformation) const override {
    for (const pcl::Correspondence& pair : correspondences) {
      add(source[pair.index_query], target[pair.index_match]);
    }
    solve(transformation);
  }

 private:
  void add(const Point& from, const Point& to) const {
    source_.emplace_back(from.x, from.y, from.z);
    target_.emplace_back(to.x, to.y, to.z);
  }

  // As PCL's: fewer than 4 pairs leave `transformation` as it was.
  void solve(Matrix4& transformation) const {
    if (source_.size() >= 4) {
      transformation = pointToPointLm(source_, target_).matrix().cast<float>();
    }
    source_.clear();
    target_.clear();
  }

  // Scratch, reused across calls (one estimator per registration object and thread).
  mutable std::vector<Eigen::Vector3d> source_, target_;
};

using PclIcpNl = icp_detail::ReusableIcp<pcl::IterativeClosestPointNonLinear<Point, Point>>;

class AnalyticIcpNl : public PclIcpNl {
 public:
  AnalyticIcpNl() { setTransformationEstimation(std::make_shared<AnalyticLmEstimation>()); }
};

}  // namespace

std::unique_ptr<RegistrationMethodImpl> prepareIcpNl(const IcpClassifierConfig& config,
                                                     const PreparedModels& models) {
  return std::make_unique<icp_detail::IcpMethod<AnalyticIcpNl>>(config, models);
}

}  // namespace granular
