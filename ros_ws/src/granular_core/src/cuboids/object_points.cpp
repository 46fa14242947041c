// The objects the fitters get: a detection's points isolated from its neighbours, the baseline
// rectangle, and the choice of fitter.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/geometry/footprint.h"
#include "levelled_object.h"

namespace granular {
namespace {

// Union-find over cells, smaller root first.
class Components {
 public:
  explicit Components(std::size_t count) : parent_(count) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) {
      parent_[std::max(a, b)] = std::min(a, b);
    }
  }

 private:
  std::vector<std::size_t> parent_;
};

std::uint64_t cellKey(std::int64_t column, std::int64_t row) {
  return (static_cast<std::uint64_t>(column) << 32) ^
         (static_cast<std::uint64_t>(row) & 0xffffffffULL);
}

}  // namespace

namespace cuboids {

std::vector<std::size_t> birdsEyeClusters(const std::vector<Eigen::Vector3d>& points,
                                          double gap) {
  std::unordered_map<std::uint64_t, std::size_t> cell_of_key;
  std::vector<std::pair<std::int64_t, std::int64_t>> cells;
  std::vector<std::size_t> cell_of_point;
  for (const Eigen::Vector3d& point : points) {
    const auto column = static_cast<std::int64_t>(std::floor(point.x() / gap));
    const auto row = static_cast<std::int64_t>(std::floor(point.y() / gap));
    const auto [found, added] = cell_of_key.emplace(cellKey(column, row), cells.size());
    if (added) {
      cells.emplace_back(column, row);
    }
    cell_of_point.push_back(found->second);
  }
  Components components(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto other = cell_of_key.find(cellKey(cells[c].first + dx, cells[c].second + dy));
        if (other != cell_of_key.end()) {
          components.join(c, other->second);
        }
      }
    }
  }
  std::vector<std::size_t> cluster;
  cluster.reserve(points.size());
  for (const std::size_t cell : cell_of_point) {
    cluster.push_back(components.find(cell));
  }
  return cluster;
}

}  // namespace cuboids

std::vector<Eigen::Vector3d> isolateObject(const std::vector<Eigen::Vector3d>& points,
                                           const std::optional<GroundPlane>& ground,
                                           const Eigen::Vector3d& centre,
                                           const Eigen::Vector3d& size,
                                           const CuboidConfig& config) {
  std::vector<Eigen::Vector3d> candidates;
  for (const Eigen::Vector3d& point : points) {
    const double height = ground ? ground->heightOf(point) : config.points.min_height;
    if (point.allFinite() && height >= config.points.min_height &&
        height <= config.points.max_height) {
      candidates.push_back(point);
    }
  }
  const std::vector<std::size_t> cluster =
      cuboids::birdsEyeClusters(candidates, config.detections.cluster_gap);
  // Per cluster: points, and points within the circle.
  const double radius = std::hypot(size.x(), size.y()) / 2;
  std::vector<std::size_t> total(candidates.size(), 0), inside(candidates.size(), 0);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    ++total[cluster[i]];
    inside[cluster[i]] += (candidates[i].head<2>() - centre.head<2>()).norm() <= radius;
  }
  std::vector<bool> keep(candidates.size(), false);
  bool any = false;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    keep[c] = 2 * inside[c] > total[c];
    any = any || keep[c];
  }
  if (!any && !candidates.empty()) {
    keep[std::max_element(inside.begin(), inside.end()) - inside.begin()] = true;
  }
  std::vector<Eigen::Vector3d> object;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (keep[cluster[i]]) {
      object.push_back(candidates[i]);
    }
  }
  return object;
}

RectangleCuboidFitter::RectangleCuboidFitter(const CuboidConfig& config) : config_(config) {
  validate(config_);
}

std::optional<FittedCuboid> RectangleCuboidFitter::fit(const ObjectView& object) const {
  const std::optional<cuboids::LevelledObject> levelled =
      cuboids::levelObject(object, config_.points);
  if (!levelled) {
    return std::nullopt;
  }
  std::vector<Eigen::Vector2d> xy;
  for (const Eigen::Vector3d& point : levelled->points) {
    xy.push_back(point.head<2>());
  }
  const Rectangle rectangle = minimumAreaRectangle(xy);
  const double floor = config_.lshape.cell;  // the least extent, as the geometric fit's
  FittedCuboid cuboid{
      kUnknownLabel, 1.0,
      cuboids::sensorBox(levelled->levelling, rectangle.centre, rectangle.yaw,
                         Eigen::Vector3d(std::max(rectangle.length, floor),
                                         std::max(rectangle.width, floor),
                                         std::max(levelled->top, floor))),
      levelled->points.size()};
  return cuboid;
}

std::unique_ptr<CuboidFitter> makeCuboidFitter(const CuboidConfig& config,
                                               std::vector<LabelledModel> models) {
  switch (config.method) {
    case CuboidMethod::kModel:
      return std::make_unique<ModelCuboidFitter>(config, std::move(models));
    case CuboidMethod::kRectangle:
      return std::make_unique<RectangleCuboidFitter>(config);
    case CuboidMethod::kGeometric:
      break;
  }
  return std::make_unique<GeometricCuboidFitter>(config);
}

}  // namespace granular
