// The road plane: PCL's RANSAC with a perpendicular-plane model on the lowest point per seed
// cell, then least squares on per-cell means.
#include <cmath>
#include <algorithm>
#include <limits>
#include <vector>

#include <Eigen/Eigenvalues>
#include <pcl/ModelCoefficients.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "granular_core/ground/ground.h"

namespace granular {
namespace {

// A dense grid of square cells of edge `size` over [-reach, reach)^2 around the sensor.
struct SquareGrid {
  double size;
  double reach;
  std::size_t side;

  SquareGrid(double cell_size, double half_extent)
      : size(cell_size),
        reach(half_extent),
        side(static_cast<std::size_t>(std::ceil(2.0 * half_extent / cell_size))) {}

  std::size_t cells() const { return side * side; }
  // The cell of (x, y), which must lie within reach (the seed region does).
  std::size_t cellOf(double x, double y) const {
    const auto column = std::min(side - 1, static_cast<std::size_t>((x + reach) / size));
    const auto row = std::min(side - 1, static_cast<std::size_t>((y + reach) / size));
    return row * side + column;
  }
};

// The horizontal region the seeds and the refinement come from.
struct SeedRegion {
  double min_range_sq, max_range_sq, cos_half_fov;
  bool all_around;

  explicit SeedRegion(const GroundPlaneConfig& config)
      : min_range_sq(config.seed_min_range * config.seed_min_range),
        max_range_sq(config.seed_max_range * config.seed_max_range),
        cos_half_fov(std::cos(config.seed_half_fov_deg * M_PI / 180.0)),
        all_around(config.seed_half_fov_deg >= 180.0) {}

  bool contains(const PointXYZIT& point) const {
    const double range_sq = double(point.x) * point.x + double(point.y) * point.y;
    if (!(range_sq > min_range_sq && range_sq < max_range_sq)) {
      return false;
    }
    // Within the half field of view of +x: x / range > cos(half fov).
    return all_around || (point.x > 0.0f && point.x * point.x > cos_half_fov * cos_half_fov *
                                                                  range_sq);
  }
};

// The plane (normal up) through the points' least-squares fit: the eigenvector of their
// covariance with the smallest eigenvalue.
bool fitPlane(const std::vector<Eigen::Vector3d>& points, GroundPlane& plane) {
  if (points.size() < 3) {
    return false;
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    mean += p;
  }
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    covariance += (p - mean) * (p - mean).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Vector3d normal = solver.eigenvectors().col(0);
  if (normal.z() < 0.0) {
    normal = -normal;
  }
  if (!normal.allFinite() || normal.z() <= 0.0) {
    return false;
  }
  plane.normal = normal;
  plane.offset = -normal.dot(mean);
  return true;
}

}  // namespace

GroundPlane estimateGroundPlane(const Cloud& cloud, const GroundPlaneConfig& config,
                                std::size_t* seeds_found, std::size_t* inliers_found) {
  const SeedRegion region(config);
  // The lowest point of each seed cell, low enough to be road; and, in the same pass over the
  // cloud, the region's points for the refinement.
  const SquareGrid seed_grid(config.seed_cell, config.seed_max_range);
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> lowest(seed_grid.cells(), kNone);
  std::vector<Eigen::Vector3d> region_points;
  const double highest_seed = -config.sensor_height + config.seed_band;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointXYZIT& point = cloud[i];
    // The region holds no point with a non-finite x or y (its range test fails on them), so
    // only z is left to test, and only in it: most returns lie outside it.
    if (!region.contains(point) || !std::isfinite(point.z)) {
      continue;
    }
    region_points.emplace_back(point.x, point.y, point.z);
    if (point.z >= highest_seed) {
      continue;
    }
    std::size_t& cell = lowest[seed_grid.cellOf(point.x, point.y)];
    if (cell == kNone || point.z < cloud[cell].z) {
      cell = i;
    }
  }
  // In cloud order, so that RANSAC's draws do not depend on the grid's layout.
  std::vector<std::size_t> seed_indices;
  for (const std::size_t index : lowest) {
    if (index != kNone) {
      seed_indices.push_back(index);
    }
  }
  std::sort(seed_indices.begin(), seed_indices.end());
  pcl::PointCloud<pcl::PointXYZ>::Ptr seeds(new pcl::PointCloud<pcl::PointXYZ>);
  for (const std::size_t index : seed_indices) {
    seeds->push_back(pcl::PointXYZ(cloud[index].x, cloud[index].y, cloud[index].z));
  }
  if (seeds_found != nullptr) {
    *seeds_found = seeds->size();
  }

  GroundPlane plane;  // no plane found: flat, sensor_height below
  plane.offset = config.sensor_height;
  std::size_t inliers = 0;
  if (seeds->size() >= 3) {
    // random = false: PCL's fixed seed, so that a cloud always gives the same plane.
    pcl::SACSegmentation<pcl::PointXYZ> ransac(false);
    ransac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
    ransac.setMethodType(pcl::SAC_RANSAC);
    ransac.setAxis(Eigen::Vector3f::UnitZ());
    ransac.setEpsAngle(config.eps_angle_deg * M_PI / 180.0);  // PCL's default 0 disables it
    ransac.setDistanceThreshold(config.inlier_distance);
    ransac.setMaxIterations(config.ransac_iterations);
    ransac.setOptimizeCoefficients(false);
    ransac.setInputCloud(seeds);
    pcl::PointIndices found;
    pcl::ModelCoefficients coefficients;
    ransac.segment(found, coefficients);
    if (coefficients.values.size() == 4 && !found.indices.empty()) {
      Eigen::Vector3d normal(coefficients.values[0], coefficients.values[1],
                             coefficients.values[2]);
      double offset = coefficients.values[3];
      const double length = normal.norm();
      if (normal.z() < 0.0) {
        normal = -normal;
        offset = -offset;
      }
      if (length > 0.0 && normal.z() > 0.0) {
        plane.normal = normal / length;
        plane.offset = offset / length;
        inliers = found.indices.size();
      }
    }
  }
  if (inliers_found != nullptr) {
    *inliers_found = inliers;
  }
  if (inliers == 0) {
    return plane;
  }

  // Refinement: least squares on the per-cell means of the region's points near the plane.
  // Each point's cell, and the rows and columns the region covers (a field of view ahead
  // covers a third of the grid): the passes clear and read those cells only.
  const SquareGrid refine_grid(config.refine_cell, config.seed_max_range);
  std::vector<std::size_t> cell_of(region_points.size());
  std::size_t first_row = refine_grid.side, last_row = 0;
  std::size_t first_column = refine_grid.side, last_column = 0;
  for (std::size_t i = 0; i < region_points.size(); ++i) {
    cell_of[i] = refine_grid.cellOf(region_points[i].x(), region_points[i].y());
    const std::size_t row = cell_of[i] / refine_grid.side;
    const std::size_t column = cell_of[i] % refine_grid.side;
    first_row = std::min(first_row, row);
    last_row = std::max(last_row, row);
    first_column = std::min(first_column, column);
    last_column = std::max(last_column, column);
  }
  std::vector<Eigen::Vector3d> sums(refine_grid.cells());
  std::vector<std::size_t> counts(refine_grid.cells());
  for (int pass = 0; pass < config.refine_passes; ++pass) {
    for (std::size_t row = first_row; row <= last_row; ++row) {
      const std::size_t from = row * refine_grid.side + first_column;
      const std::size_t to = row * refine_grid.side + last_column + 1;
      std::fill(sums.begin() + from, sums.begin() + to, Eigen::Vector3d::Zero());
      std::fill(counts.begin() + from, counts.begin() + to, 0);
    }
    for (std::size_t i = 0; i < region_points.size(); ++i) {
      const Eigen::Vector3d& p = region_points[i];
      if (std::abs(plane.heightOf(p)) < config.inlier_distance) {
        sums[cell_of[i]] += p;
        ++counts[cell_of[i]];
      }
    }
    // In cell order: the same cloud gives the same plane to the bit.
    std::vector<Eigen::Vector3d> points;
    for (std::size_t row = first_row; row <= last_row; ++row) {
      for (std::size_t cell = row * refine_grid.side + first_column;
           cell <= row * refine_grid.side + last_column; ++cell) {
        if (counts[cell] > 0) {
          points.push_back(sums[cell] / static_cast<double>(counts[cell]));
        }
      }
    }
    GroundPlane refined;
    if (!fitPlane(points, refined) ||
        std::acos(std::min(1.0, refined.normal.z())) > config.eps_angle_deg * M_PI / 180.0) {
      break;
    }
    plane = refined;
  }
  return plane;
}

}  // namespace granular
