#include "granular_core/models/concatenate.h"

#include <algorithm>
#include <cmath>

namespace granular {

ModelCloud concatenate(const std::vector<ModelCloud>& clouds) {
  std::size_t total = 0;
  for (const ModelCloud& cloud : clouds) {
    total += cloud.size();
  }
  ModelCloud model;
  model.reserve(total);
  for (const ModelCloud& cloud : clouds) {
    model.insert(model.end(), cloud.begin(), cloud.end());
  }
  return model;
}

const char* sideName(Side side) {
  switch (side) {
    case Side::kFront:
      return "front";
    case Side::kBack:
      return "back";
    case Side::kLeft:
      return "left";
    case Side::kRight:
      return "right";
  }
  return "unknown";
}

Eigen::Vector2d halfExtents(const std::vector<ModelCloud>& objects) {
  Eigen::Vector2d half(1e-3, 1e-3);
  for (const ModelCloud& object : objects) {
    for (const pcl::PointXYZ& point : object.points) {
      half.x() = std::max(half.x(), static_cast<double>(std::abs(point.x)));
      half.y() = std::max(half.y(), static_cast<double>(std::abs(point.y)));
    }
  }
  return half;
}

Side sideSeen(const ModelCloud& object, const Eigen::Vector2d& half_extent) {
  if (object.empty()) {
    return Side::kFront;
  }
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const pcl::PointXYZ& point : object.points) {
    centroid += Eigen::Vector2d(point.x, point.y);
  }
  centroid /= static_cast<double>(object.size());
  const Eigen::Vector2d scaled = centroid.cwiseQuotient(half_extent);
  if (std::abs(scaled.x()) >= std::abs(scaled.y())) {
    return scaled.x() >= 0.0 ? Side::kFront : Side::kBack;
  }
  return scaled.y() >= 0.0 ? Side::kLeft : Side::kRight;
}

SeedSelection selectSeedObjects(const std::vector<ModelCloud>& objects, const SeedConfig& config) {
  const Eigen::Vector2d half = halfExtents(objects);
  std::vector<std::size_t> order(objects.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = i;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return objects[a].size() > objects[b].size();
  });
  std::vector<Side> side_of(objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    side_of[i] = sideSeen(objects[i], half);
  }

  SeedSelection selection;
  for (const Side side : {Side::kFront, Side::kBack, Side::kLeft, Side::kRight}) {
    std::size_t chosen = 0;
    for (const std::size_t index : order) {
      if (chosen == config.objects_per_side) {
        break;
      }
      if (side_of[index] == side) {
        selection.indices.push_back(index);
        selection.sides.push_back(side);
        ++chosen;
      }
    }
    if (chosen == 0) {
      selection.missing_sides.push_back(side);
    }
  }
  return selection;
}

}  // namespace granular
