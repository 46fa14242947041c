#pragma once

#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <pcl/search/kdtree.h>

#include "granular_core/point_types.h"
#include "granular_core/search/bounded_grid.h"
#include "granular_core/search/distance_bound.h"
#include "granular_core/search/nearest_grid.h"
#include "granular_core/search/nearest_points.h"

namespace granular {

/// The nearest-point search of a fixed class model, shared read-only by all threads. It
/// answers ICP's single-neighbour queries from a BoundedGrid of the model when they have a
/// correspondence bound, otherwise from a NearestGrid and, for the queries its rings cannot
/// settle, from a NearestPoints kd-tree; and the fitness score from the BoundedGrid for the
/// points within the bound, when there is one, and from the kd-tree for the rest, four object
/// points at a time. Every distance is the one PCL's KdTreeFLANN gives,
/// bit for bit, without its cost per query: PCL allocates and enters an OpenMP parallel region
/// (FLANN's knnSearch) for each point, which for small objects costs more than the search.
/// Two searches are also bounded, without changing their answers:
///  - ICP's correspondence estimation discards a nearest point beyond the maximum
///    correspondence distance, so a search needs to look no farther (setCorrespondenceBound);
///  - fitness() bounds each kd-tree search by the distance of the scan point before its
///    packet plus the step between the two: neighbouring scan points have neighbouring
///    nearest points.
///
/// It is a pcl::search::KdTree so that PCL's ICP takes it as its target search
/// (setSearchMethodTarget); the virtual methods it overrides are PCL 1.13's (see
/// test_pcl_internals.cpp).
class NearestTree : public pcl::search::KdTree<pcl::PointXYZ> {
 public:
  using Ptr = std::shared_ptr<NearestTree>;
  using pcl::search::KdTree<pcl::PointXYZ>::nearestKSearch;

  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override;

  /// Single-neighbour queries beyond `max_distance` (m) then report no neighbour (an infinite
  /// distance), which PCL's correspondence estimation discards as it would the real one; a
  /// BoundedGrid of the model is built for them, so call it before any query (before
  /// setInputCloud, and only that grid is built).
  void setCorrespondenceBound(double max_distance);

  int nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override;

  /// A model point, by its index in the cloud given, and its squared distance (m^2).
  struct Neighbour {
    bool found = false;
    pcl::index_t index = 0;
    float squared = std::numeric_limits<float>::infinity();
  };

  /// ICP's correspondence search: what nearestKSearch(point, 1, ...) answers, without its
  /// two vectors. Not found: no model point within the correspondence bound (or no bound
  /// set and no model point at all).
  Neighbour nearestWithinBound(const pcl::PointXYZ& point) const {
    Neighbour neighbour;
    if (mapping_.empty()) {
      return neighbour;
    }
    const float query[3] = {point.x, point.y, point.z};
    const NearestGrid::Result nearest =
        bounded_ ? bounded_->nearest(query) : nearestWithin(query, correspondence_bound_);
    if (nearest.found) {
      neighbour.found = true;
      neighbour.index = mapping_[nearest.index];
      neighbour.squared = nearest.distance;
    }
    return neighbour;
  }

  /// What PCL's Registration::getFitnessScore() gives for `source` aligned by `transform` on
  /// this model: the mean squared distance of each transformed point to its nearest model
  /// point (m^2); the largest double for an empty source or model.
  double fitness(const ModelCloud& source, const Eigen::Matrix4f& transform) const;

  /// The source as fitness() measures it: `source` moved by `transform` (PCL's
  /// transformPointCloud), into `moved`.
  static void moveForFitness(const ModelCloud& source, const Eigen::Matrix4f& transform,
                             ModelCloud& moved);
  /// fitness() of a source moved by moveForFitness: the same value to the bit.
  double fitnessOfMoved(const ModelCloud& moved) const;
  /// fitnessOfMoved(moved), and each moved point's squared distance to its nearest model
  /// point in `squared_distances` (resized; empty for an empty source or model).
  double fitnessOfMoved(const ModelCloud& moved, std::vector<float>& squared_distances) const;

  /// Builds the DistanceBound that fitnessLowerBound() reads (cells `cell` m wide, `margin` m
  /// beyond the model's box); after setInputCloud. Without it the lower bound is 0.
  void buildFitnessBound(float cell, float margin);
  /// At most fitnessOfMoved(moved), in constant time a point; 0 without buildFitnessBound.
  double fitnessLowerBound(const ModelCloud& moved) const;

 private:
  // The nearest point closer than `bound` (squared): from the grid, or from the kd-tree when
  // the grid cannot settle it, bounded by what the grid found.
  NearestGrid::Result nearestWithin(const float query[3], float bound) const;

  // The single-neighbour search for the current bound: a BoundedGrid for a finite one,
  // otherwise a NearestGrid, with the kd-tree for what its rings cannot settle. Only one of
  // the two grids is built.
  void buildNeighbourGrid();

  std::vector<float> points_;
  pcl::Indices mapping_;
  std::unique_ptr<NearestGrid> grid_;     ///< without a correspondence bound
  std::unique_ptr<BoundedGrid> bounded_;  ///< with one
  std::unique_ptr<NearestPoints> tree_;
  std::unique_ptr<DistanceBound> fitness_bound_;
  float correspondence_bound_ = std::numeric_limits<float>::infinity();
};

}  // namespace granular
