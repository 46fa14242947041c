#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "granular_core/registration/registration_config.h"
#include "granular_core/point_types.h"

namespace granular {

/// PCL 1.13's NormalDistributionsTransform (Magnusson 2009) against one fixed model: the same
/// voxel cells (pcl::VoxelGridCovariance), the same Newton steps and More-Thuente line search,
/// the same numbers, bit for bit, for the same source. What it does not do is what made PCL's
/// NDT slow for many small objects against few models:
///  - the cells near a point come from a grid of the cells' centroids, not from a FLANN radius
///    search (which allocates and opens an OpenMP region per point) and a std::map per cell;
///  - a point's derivatives with respect to the pose are computed once per point, not once per
///    cell it meets, and the Hessian's products once per cell, not once per entry.
/// The cells are built once; align() is const and safe to call from many threads.
class NdtMatcher {
 public:
  struct Result {
    /// PCL's hasConverged(): the last step was short enough, or max_iterations was reached.
    bool converged = false;
    int iterations = 0;         ///< PCL's getFinalNumIteration()
    double likelihood = 0.0;    ///< PCL's getTransformationLikelihood()
    Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();  ///< getFinalTransformation()
  };

  /// The model's cells as NDT's setInputTarget() builds them from `config`.
  NdtMatcher(const ModelCloud& model, const NdtClassifierConfig& config);

  /// Cells (voxels with enough model points); with none, align() returns at once, as PCL does.
  std::size_t cells() const { return means_.size(); }

  /// What PCL's align() gives for `source` (at least one point) from the identity.
  Result align(const ModelCloud& source) const;

 private:
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  struct Pass;

  // The cells whose centroid lies within the resolution of `point`, in FLANN's order (by
  // squared distance, then by index).
  void neighbours(const pcl::PointXYZ& point, std::vector<std::uint32_t>& found,
                  std::vector<float>& distances) const;
  // PCL's computeDerivatives(): the score of `moved` (the source under `transform`), its
  // gradient and, when asked, its Hessian.
  double derivatives(const ModelCloud& source, const ModelCloud& moved,
                     const Vector6d& transform, bool compute_hessian, Vector6d& gradient,
                     Matrix6d& hessian, Pass& pass) const;
  // PCL's computeStepLengthMT(): the step along `direction` and the state there (the score,
  // its gradient, the moved source and its transform; not the Hessian, which align() computes
  // when it needs it).
  double stepLength(const ModelCloud& source, const Vector6d& transform, Vector6d& direction,
                    double step_init, double& score, Vector6d& gradient, ModelCloud& moved,
                    Eigen::Matrix4f& final_transform, Pass& pass) const;

  NdtClassifierConfig config_;
  double gauss_d1_ = 0.0;
  double gauss_d2_ = 0.0;
  float radius_squared_ = 0.0f;  ///< as FLANN compares squared distances: float(r * r)

  // Per cell, in the order of PCL's centroid cloud (FLANN's indices).
  std::vector<Eigen::Vector3d> means_;
  std::vector<Eigen::Matrix3d> inverse_covariances_;

  // A grid of buckets a little larger than the radius over the centroids. Each bucket lists
  // the cells whose centroids lie in it or in the 26 buckets around it: the cells within the
  // radius of a point are among those listed in the point's bucket.
  struct Candidate {
    float centroid[3];
    std::uint32_t cell;
  };
  float bucket_ = 1.0f;
  float origin_[3] = {0.0f, 0.0f, 0.0f};
  int size_[3] = {0, 0, 0};
  std::vector<std::uint32_t> bucket_start_;  ///< candidates of bucket b: [start[b], start[b + 1])
  std::vector<Candidate> candidates_;
};

}  // namespace granular
