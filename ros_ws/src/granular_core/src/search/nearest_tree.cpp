#include "granular_core/search/nearest_tree.h"

#include <algorithm>
#include <cmath>

#include <pcl/common/transforms.h>

namespace granular {
namespace {

// Rings of grid cells a query searches before it asks the kd-tree: one settles the queries on
// and near the model's surface, which are most of them.
constexpr int kGridRings = 1;

}  // namespace

void NearestTree::setInputCloud(const PointCloudConstPtr& cloud,
                                const IndicesConstPtr& indices) {
  pcl::search::KdTree<pcl::PointXYZ>::setInputCloud(cloud, indices);
  points_.clear();
  mapping_.clear();
  const auto add = [&](pcl::index_t i) {
    const pcl::PointXYZ& point = (*cloud)[static_cast<std::size_t>(i)];
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      points_.insert(points_.end(), {point.x, point.y, point.z});
      mapping_.push_back(i);
    }
  };
  if (indices) {
    for (const pcl::index_t i : *indices) {
      add(i);
    }
  } else {
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      add(static_cast<pcl::index_t>(i));
    }
  }
  buildNeighbourGrid();
  tree_ = std::make_unique<NearestPoints>(points_.data(), mapping_.size());
  fitness_bound_.reset();
}

void NearestTree::buildFitnessBound(float cell, float margin) {
  fitness_bound_.reset();
  if (!mapping_.empty()) {
    fitness_bound_ =
        std::make_unique<DistanceBound>(points_.data(), mapping_.size(), *tree_, cell, margin);
  }
}

double NearestTree::fitnessLowerBound(const ModelCloud& moved) const {
  if (!fitness_bound_ || moved.empty()) {
    return 0.0;
  }
  // Summed in the order fitnessOfMoved sums, each term at most its term there: so is the mean.
  double sum = 0.0;
  for (const pcl::PointXYZ& point : moved) {
    sum += fitness_bound_->squaredLowerBound(point.data);
  }
  return sum / static_cast<double>(moved.size());
}

void NearestTree::setCorrespondenceBound(double max_distance) {
  // The smallest float above every float distance d with d <= max_distance^2 (double), as PCL
  // compares them.
  const double limit = max_distance * max_distance;
  float bound = static_cast<float>(limit);
  if (static_cast<double>(bound) < limit) {
    bound = std::nextafter(bound, std::numeric_limits<float>::infinity());
  }
  correspondence_bound_ = std::nextafter(bound, std::numeric_limits<float>::infinity());
  buildNeighbourGrid();
}

void NearestTree::buildNeighbourGrid() {
  if (std::isfinite(correspondence_bound_)) {
    bounded_ = std::make_unique<BoundedGrid>(points_.data(), mapping_.size(),
                                             correspondence_bound_);
    grid_.reset();
  } else {
    grid_ = std::make_unique<NearestGrid>(points_.data(), mapping_.size(), kGridRings);
    bounded_.reset();
  }
}

int NearestTree::nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                                std::vector<float>& k_sqr_distances) const {
  if (k != 1 || mapping_.empty()) {
    return pcl::search::KdTree<pcl::PointXYZ>::nearestKSearch(point, k, k_indices,
                                                              k_sqr_distances);
  }
  const Neighbour nearest = nearestWithinBound(point);
  k_indices.assign(1, nearest.index);
  k_sqr_distances.assign(1, nearest.squared);
  return 1;
}

double NearestTree::fitness(const ModelCloud& source, const Eigen::Matrix4f& transform) const {
  ModelCloud moved;
  moveForFitness(source, transform, moved);
  return fitnessOfMoved(moved);
}

void NearestTree::moveForFitness(const ModelCloud& source, const Eigen::Matrix4f& transform,
                                 ModelCloud& moved) {
  pcl::transformPointCloud(source, moved, transform);
}

double NearestTree::fitnessOfMoved(const ModelCloud& moved) const {
  std::vector<float> distances;
  return fitnessOfMoved(moved, distances);
}

double NearestTree::fitnessOfMoved(const ModelCloud& moved, std::vector<float>& distances) const {
  if (mapping_.empty() || moved.empty()) {
    distances.clear();
    return std::numeric_limits<double>::max();
  }
  distances.resize(moved.size());
  // With a correspondence bound, the points ICP paired (within it) are answered by its
  // BoundedGrid from one cell's list; the kd-tree answers the rest.
  std::vector<std::size_t> far;
  far.reserve(moved.size());
  for (std::size_t i = 0; i < moved.size(); ++i) {
    if (bounded_) {
      const NearestGrid::Result nearest = bounded_->nearest(moved[i].data);
      if (nearest.found) {
        distances[i] = nearest.distance;
        continue;
      }
    }
    far.push_back(i);
  }
  // Most points of most pairs lie far from the model (the wrong classes), where the grid's
  // rings cannot settle them: the kd-tree takes kPacket of them at a time, each bounded by the
  // nearest model point of the scan point before the packet (all before it are known): at most
  // that point's distance plus the step between the two points (widened for rounding).
  constexpr int kPacket = NearestPoints::kPacket;
  for (std::size_t first = 0; first < far.size(); first += kPacket) {
    float queries[kPacket][3];
    float bounds[kPacket];
    for (int lane = 0; lane < kPacket; ++lane) {
      // The last packet is filled up with its last point again.
      const std::size_t point = far[std::min(first + lane, far.size() - 1)];
      std::copy(moved[point].data, moved[point].data + 3, queries[lane]);
      bounds[lane] = std::numeric_limits<float>::infinity();
      if (far[first] > 0) {
        const pcl::PointXYZ& previous = moved[far[first] - 1];
        const double step =
            std::sqrt(static_cast<double>(flannSquaredDistance(queries[lane], previous.data)));
        const double reach = std::sqrt(static_cast<double>(distances[far[first] - 1])) + step;
        bounds[lane] = static_cast<float>(reach * reach * (1.0 + 1.0e-5) + 1.0e-30);
      }
    }
    float nearest[kPacket];
    tree_->nearestDistances(queries, bounds, nearest);
    for (std::size_t lane = 0; lane < std::min<std::size_t>(kPacket, far.size() - first);
         ++lane) {
      distances[far[first + lane]] = nearest[lane];
    }
  }
  double sum = 0.0;
  for (const float distance : distances) {
    sum += distance;
  }
  return sum / static_cast<double>(distances.size());
}

NearestGrid::Result NearestTree::nearestWithin(const float query[3], float bound) const {
  NearestGrid::Result nearest = grid_->nearest(query, bound);
  if (nearest.resolved) {
    return nearest;
  }
  const NearestPoints::Result exact = tree_->nearest(
      query, nearest.found ? std::nextafter(nearest.distance, std::numeric_limits<float>::infinity())
                           : bound);
  nearest.found = exact.found;
  nearest.index = exact.index;
  nearest.distance = exact.distance;
  return nearest;
}

}  // namespace granular
