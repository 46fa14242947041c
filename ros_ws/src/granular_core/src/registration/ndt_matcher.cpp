// PCL 1.13's NDT, pcl/registration/impl/ndt.hpp, restructured for speed and kept to its
// arithmetic: what does not search the model is PCL's own code (NdtParts), and where this file
// restates PCL it evaluates the same Eigen expressions on the same types, so that the results
// agree bit for bit (test_classification and bench_registration check).
#include "granular_core/registration/ndt_matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <pcl/common/transforms.h>
#include <pcl/filters/voxel_grid_covariance.h>
#include <pcl/registration/ndt.h>

#include "granular_core/search/nearest_points.h"
#include "granular_core/search/grid_cells.h"

namespace granular {
namespace {

using Point = pcl::PointXYZ;

// PCL's voxel cells with the map from centroid (FLANN index) to cell, which PCL keeps protected.
class ModelCells : public pcl::VoxelGridCovariance<Point> {
 public:
  const std::vector<int>& centroidLeaves() const { return voxel_centroids_leaf_indices_; }
};

// The parts of PCL's NDT that do not search the model, which PCL keeps protected: the
// More-Thuente interval update and trial step, and the derivatives of the transformed points
// with respect to the pose (computeAngleDerivatives, computePointDerivatives), which PCL
// leaves in its members of those names.
class NdtParts : public pcl::NormalDistributionsTransform<Point, Point> {
  using Pcl = pcl::NormalDistributionsTransform<Point, Point>;

 public:
  using Pcl::auxilaryFunction_dPsiMT;
  using Pcl::auxilaryFunction_PsiMT;
  using Pcl::computeAngleDerivatives;
  using Pcl::computePointDerivatives;
  using Pcl::trialValueSelectionMT;
  using Pcl::updateIntervalMT;

  // The point derivatives as computeTransformation() sets them up before its first step.
  NdtParts() {
    point_jacobian_.setZero();
    point_jacobian_.block<3, 3>(0, 0).setIdentity();
    point_hessian_.setZero();
  }
  const Eigen::Matrix<double, 3, 6>& pointJacobian() const { return point_jacobian_; }
  const Eigen::Matrix<double, 18, 6>& pointHessian() const { return point_hessian_; }
};

// Buckets in the centroid grid at most; a larger model gets larger buckets.
constexpr double kMaxBuckets = 8.0e6;

// pcl::NormalDistributionsTransform::convertTransform().
Eigen::Matrix4f matrixOf(const Eigen::Matrix<double, 6, 1>& x) {
  const Eigen::Transform<float, 3, Eigen::Affine> affine =
      Eigen::Translation<float, 3>(x.head<3>().cast<float>()) *
      Eigen::AngleAxis<float>(static_cast<float>(x(3)), Eigen::Vector3f::UnitX()) *
      Eigen::AngleAxis<float>(static_cast<float>(x(4)), Eigen::Vector3f::UnitY()) *
      Eigen::AngleAxis<float>(static_cast<float>(x(5)), Eigen::Vector3f::UnitZ());
  return affine.matrix();
}

}  // namespace

// One alignment's scratch: PCL's derivative state, and the neighbour lists.
struct NdtMatcher::Pass {
  NdtParts ndt;
  std::vector<std::uint32_t> cells;
  std::vector<float> distances;
};

NdtMatcher::NdtMatcher(const ModelCloud& model, const NdtClassifierConfig& config)
    : config_(config) {
  // NormalDistributionsTransform's constants (eq. 6.8) and its target_cells_, as
  // setMinPointPerVoxel, setResolution and setInputTarget leave them.
  const float resolution = static_cast<float>(config.resolution);
  const double gauss_c1 = 10 * (1 - config.outlier_ratio);
  const double gauss_c2 = config.outlier_ratio / std::pow(resolution, 3);
  const double gauss_d3 = -std::log(gauss_c2);
  gauss_d1_ = -std::log(gauss_c1 + gauss_c2) - gauss_d3;
  gauss_d2_ = -2 * std::log((-std::log(gauss_c1 * std::exp(-0.5) + gauss_c2) - gauss_d3) /
                            gauss_d1_);
  radius_squared_ = static_cast<float>(static_cast<double>(resolution) * resolution);

  ModelCells cells;
  cells.setMinPointPerVoxel(config.min_points_per_voxel);
  cells.setLeafSize(resolution, resolution, resolution);
  cells.setInputCloud(model.makeShared());
  cells.filter(true);
  const ModelCloud& centroids = *cells.getCentroids();
  if (centroids.empty()) {
    return;
  }
  for (std::size_t i = 0; i < centroids.size(); ++i) {
    const auto leaf = cells.getLeaves().find(
        static_cast<std::size_t>(cells.centroidLeaves()[i]));
    means_.push_back(leaf->second.getMean());
    inverse_covariances_.push_back(leaf->second.getInverseCov());
  }

  // The bucket grid: a bucket a little wider than the radius, so that a centroid within the
  // radius of a point is never two buckets away, whatever the rounding, and one bucket more
  // on every side, so that a point beyond the grid has no cell near. Each bucket lists the
  // cells of the 27 buckets around it, with their centroids, for one look-up per point.
  float low[3], high[3];
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] = high[axis] = centroids[0].data[axis];
  }
  for (const Point& centroid : centroids) {
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = std::min(low[axis], centroid.data[axis]);
      high[axis] = std::max(high[axis], centroid.data[axis]);
    }
  }
  double bucket = 1.01 * resolution;
  double volume = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    volume *= static_cast<double>(high[axis] - low[axis]) + 3.0 * bucket;
  }
  bucket = std::max(bucket, std::cbrt(volume / kMaxBuckets));
  bucket_ = static_cast<float>(bucket);
  for (int axis = 0; axis < 3; ++axis) {
    origin_[axis] = low[axis] - bucket_;
    size_[axis] = static_cast<int>((high[axis] - low[axis]) / bucket_) + 3;
  }
  const std::size_t buckets = static_cast<std::size_t>(size_[0]) * size_[1] * size_[2];
  std::vector<std::array<int, 3>> bucket_of(means_.size());
  for (std::size_t i = 0; i < means_.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      bucket_of[i][axis] = std::clamp(
          static_cast<int>((centroids[i].data[axis] - origin_[axis]) / bucket_), 1,
          size_[axis] - 2);
    }
  }
  const auto forEachNeighbour = [&](const std::array<int, 3>& centre, const auto& visit) {
    const int low[3] = {centre[0] - 1, centre[1] - 1, centre[2] - 1};
    const int high[3] = {centre[0] + 1, centre[1] + 1, centre[2] + 1};
    forEachCell(low, high, size_, visit);
  };
  bucket_start_.assign(buckets + 1, 0);
  for (std::size_t i = 0; i < means_.size(); ++i) {
    forEachNeighbour(bucket_of[i], [&](std::size_t b) { ++bucket_start_[b + 1]; });
  }
  for (std::size_t b = 0; b < buckets; ++b) {
    bucket_start_[b + 1] += bucket_start_[b];
  }
  std::vector<std::uint32_t> next(bucket_start_.begin(), bucket_start_.end() - 1);
  candidates_.resize(bucket_start_.back());
  for (std::size_t i = 0; i < means_.size(); ++i) {
    const Candidate candidate{{centroids[i].x, centroids[i].y, centroids[i].z},
                              static_cast<std::uint32_t>(i)};
    forEachNeighbour(bucket_of[i], [&](std::size_t b) { candidates_[next[b]++] = candidate; });
  }
}

void NdtMatcher::neighbours(const Point& point, std::vector<std::uint32_t>& found,
                            std::vector<float>& distances) const {
  found.clear();
  distances.clear();
  int coordinates[3];
  if (!cellOf(point.data, origin_, bucket_, size_, coordinates)) {
    return;  // beyond the grid (or not finite): no cell is near
  }
  const std::size_t bucket = cellIndex(coordinates, size_);
  for (std::uint32_t k = bucket_start_[bucket]; k < bucket_start_[bucket + 1]; ++k) {
    // FLANN's test: the squared distance strictly below the squared radius.
    const float distance = flannSquaredDistance(candidates_[k].centroid, point.data);
    if (distance < radius_squared_) {
      found.push_back(candidates_[k].cell);
      distances.push_back(distance);
    }
  }
  // FLANN's sorted order: by distance, then by index. The lists are short.
  for (std::size_t i = 1; i < found.size(); ++i) {
    const std::uint32_t cell = found[i];
    const float distance = distances[i];
    std::size_t j = i;
    while (j > 0 && (distances[j - 1] > distance ||
                     (distances[j - 1] == distance && found[j - 1] > cell))) {
      found[j] = found[j - 1];
      distances[j] = distances[j - 1];
      --j;
    }
    found[j] = cell;
    distances[j] = distance;
  }
}

double NdtMatcher::derivatives(const ModelCloud& source, const ModelCloud& moved,
                               const Vector6d& transform, bool compute_hessian,
                               Vector6d& gradient, Matrix6d& hessian, Pass& pass) const {
  gradient.setZero();
  hessian.setZero();
  double score = 0;
  pass.ndt.computeAngleDerivatives(transform, compute_hessian);
  const Eigen::Matrix<double, 3, 6>& jacobian = pass.ndt.pointJacobian();
  const Eigen::Matrix<double, 18, 6>& point_hessian = pass.ndt.pointHessian();
  for (std::size_t idx = 0; idx < source.size(); ++idx) {
    neighbours(moved[idx], pass.cells, pass.distances);
    if (pass.cells.empty()) {
      continue;
    }
    // Once per point here, where PCL repeats it for every cell the point meets.
    pass.ndt.computePointDerivatives(source[idx].getVector3fMap().template cast<double>(),
                                     compute_hessian);
    for (const std::uint32_t cell : pass.cells) {
      const Eigen::Vector3d x_trans =
          moved[idx].getVector3fMap().template cast<double>() - means_[cell];
      const Eigen::Matrix3d& c_inv = inverse_covariances_[cell];
      // updateDerivatives(): eq. 6.9, 6.10, 6.12 and 6.13 [Magnusson 2009].
      double e_x_cov_x = std::exp(-gauss_d2_ * x_trans.dot(c_inv * x_trans) / 2);
      const double score_inc = -gauss_d1_ * e_x_cov_x;
      e_x_cov_x = gauss_d2_ * e_x_cov_x;
      if (e_x_cov_x > 1 || e_x_cov_x < 0 || std::isnan(e_x_cov_x)) {
        continue;
      }
      e_x_cov_x *= gauss_d1_;
      // PCL evaluates c_inv * J_j and x_trans . (c_inv * J_j) again for every Hessian entry.
      // The first three columns of J are unit vectors, so c_inv * J_j is c_inv's column and
      // J_j . v is v's entry: the same values without the products by 0 and 1.
      Eigen::Vector3d cov_dxd[6];
      double x_dot_cov_dxd[6];
      for (int i = 0; i < 6; ++i) {
        cov_dxd[i] = i < 3 ? Eigen::Vector3d(c_inv.col(i))
                           : Eigen::Vector3d(c_inv * jacobian.col(i));
        x_dot_cov_dxd[i] = x_trans.dot(cov_dxd[i]);
        gradient(i) += x_dot_cov_dxd[i] * e_x_cov_x;
      }
      if (compute_hessian) {
        // The point's second derivatives are zero but for rotation pairs (eq. 6.20), and
        // PCL's blocks (3i, j) and (3j, i) hold the same vector.
        double x_dot_cov_hessian[3][3];
        for (int i = 3; i < 6; ++i) {
          for (int j = i; j < 6; ++j) {
            x_dot_cov_hessian[i - 3][j - 3] = x_dot_cov_hessian[j - 3][i - 3] =
                x_trans.dot(c_inv * point_hessian.block<3, 1>(3 * i, j));
          }
        }
        for (int i = 0; i < 6; ++i) {
          for (int j = 0; j < 6; ++j) {
            const double second =
                (i >= 3 && j >= 3) ? x_dot_cov_hessian[i - 3][j - 3] : 0.0;
            const double first = j < 3 ? cov_dxd[i](j) : jacobian.col(j).dot(cov_dxd[i]);
            hessian(i, j) += e_x_cov_x * (-gauss_d2_ * x_dot_cov_dxd[i] * x_dot_cov_dxd[j] +
                                          second + first);
          }
        }
      }
      score += score_inc;
    }
  }
  return score;
}

double NdtMatcher::stepLength(const ModelCloud& source, const Vector6d& transform,
                              Vector6d& direction, double step_init, double& score,
                              Vector6d& gradient, ModelCloud& moved,
                              Eigen::Matrix4f& final_transform, Pass& pass) const {
  // computeStepLengthMT() [More, Thuente 1994], its helpers PCL's own.
  // PCL computes the Hessian at the first trial too; align() computes it where the search
  // stops, and only when another step follows. Every trial here asks for none.
  Matrix6d no_hessian;
  const NdtParts& mt = pass.ndt;
  const double step_max = config_.step_size;
  const double step_min = config_.transformation_epsilon / 2;
  const double phi_0 = -score;
  double d_phi_0 = -(gradient.dot(direction));
  if (d_phi_0 >= 0) {
    if (d_phi_0 == 0) {
      return 0;
    }
    d_phi_0 *= -1;
    direction *= -1;
  }
  const int max_step_iterations = 10;
  int step_iterations = 0;
  const double mu = 1.e-4;
  const double nu = 0.9;
  double a_l = 0, a_u = 0;
  double f_l = mt.auxilaryFunction_PsiMT(a_l, phi_0, phi_0, d_phi_0, mu);
  double g_l = mt.auxilaryFunction_dPsiMT(d_phi_0, d_phi_0, mu);
  double f_u = mt.auxilaryFunction_PsiMT(a_u, phi_0, phi_0, d_phi_0, mu);
  double g_u = mt.auxilaryFunction_dPsiMT(d_phi_0, d_phi_0, mu);
  bool interval_converged = (step_max - step_min) < 0, open_interval = true;

  double a_t = step_init;
  a_t = std::min(a_t, step_max);
  a_t = std::max(a_t, step_min);
  Vector6d x_t = transform + direction * a_t;
  final_transform = matrixOf(x_t);
  pcl::transformPointCloud(source, moved, final_transform);
  score = derivatives(source, moved, x_t, false, gradient, no_hessian, pass);

  double phi_t = -score;
  double d_phi_t = -(gradient.dot(direction));
  double psi_t = mt.auxilaryFunction_PsiMT(a_t, phi_t, phi_0, d_phi_0, mu);
  double d_psi_t = mt.auxilaryFunction_dPsiMT(d_phi_t, d_phi_0, mu);
  while (!interval_converged && step_iterations < max_step_iterations &&
         !(psi_t <= 0 && d_phi_t <= -nu * d_phi_0)) {
    if (open_interval) {
      a_t = mt.trialValueSelectionMT(a_l, f_l, g_l, a_u, f_u, g_u, a_t, psi_t, d_psi_t);
    } else {
      a_t = mt.trialValueSelectionMT(a_l, f_l, g_l, a_u, f_u, g_u, a_t, phi_t, d_phi_t);
    }
    a_t = std::min(a_t, step_max);
    a_t = std::max(a_t, step_min);
    x_t = transform + direction * a_t;
    final_transform = matrixOf(x_t);
    pcl::transformPointCloud(source, moved, final_transform);
    score = derivatives(source, moved, x_t, false, gradient, no_hessian, pass);

    phi_t = -score;
    d_phi_t = -(gradient.dot(direction));
    psi_t = mt.auxilaryFunction_PsiMT(a_t, phi_t, phi_0, d_phi_0, mu);
    d_psi_t = mt.auxilaryFunction_dPsiMT(d_phi_t, d_phi_0, mu);
    if (open_interval && (psi_t <= 0 && d_psi_t >= 0)) {
      open_interval = false;
      f_l += phi_0 - mu * d_phi_0 * a_l;
      g_l += mu * d_phi_0;
      f_u += phi_0 - mu * d_phi_0 * a_u;
      g_u += mu * d_phi_0;
    }
    if (open_interval) {
      interval_converged =
          mt.updateIntervalMT(a_l, f_l, g_l, a_u, f_u, g_u, a_t, psi_t, d_psi_t);
    } else {
      interval_converged =
          mt.updateIntervalMT(a_l, f_l, g_l, a_u, f_u, g_u, a_t, phi_t, d_phi_t);
    }
    step_iterations++;
  }
  return a_t;
}

NdtMatcher::Result NdtMatcher::align(const ModelCloud& source) const {
  Result result;
  if (means_.empty() || source.empty()) {
    return result;  // PCL reports an error and leaves everything as it was
  }
  Pass pass;
  ModelCloud moved = source;  // align() starts from the source itself (an identity guess)

  // computeTransformation(): the pose vector of the identity, as PCL derives it.
  Eigen::Transform<float, 3, Eigen::Affine, Eigen::ColMajor> start;
  start.matrix() = result.transform;
  const Eigen::Vector3f init_translation = start.translation();
  const Eigen::Vector3f init_rotation = start.rotation().eulerAngles(0, 1, 2);
  Vector6d transform;
  transform << init_translation.cast<double>(), init_rotation.cast<double>();

  Vector6d gradient;
  Matrix6d hessian;
  double score = derivatives(source, moved, transform, true, gradient, hessian, pass);
  while (!result.converged) {
    // Newton's step (line 23 of Algorithm 2 [Magnusson 2009]), then its length.
    const Eigen::JacobiSVD<Matrix6d> sv(hessian, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Vector6d delta = sv.solve(-gradient);
    double delta_norm = delta.norm();
    if (delta_norm == 0 || std::isnan(delta_norm)) {
      result.likelihood = score / static_cast<double>(source.size());
      result.converged = delta_norm == 0;
      return result;
    }
    delta /= delta_norm;
    delta_norm = stepLength(source, transform, delta, delta_norm, score, gradient, moved,
                            result.transform, pass);
    delta *= delta_norm;
    const Eigen::Matrix4f step = matrixOf(delta);
    transform += delta;
    const double translation_sqr = step.block<3, 1>(0, 3).squaredNorm();
    result.iterations++;
    // PCL's test with transformation_rotation_epsilon_ left at 0.
    if (result.iterations >= config_.max_iterations ||
        (config_.transformation_epsilon > 0 &&
         translation_sqr <= config_.transformation_epsilon)) {
      result.converged = true;
    } else {
      // The Hessian where the search stopped, for the next step (PCL's, from the line
      // search's evaluation there or its computeHessian(): the same values). A run that
      // stops after this step never uses it, and tuned NDT's steps, capped by its step_size,
      // are within its transformation_epsilon: it stops after the first.
      score = derivatives(source, moved, transform, true, gradient, hessian, pass);
    }
  }
  result.likelihood = score / static_cast<double>(source.size());
  return result;
}

}  // namespace granular
