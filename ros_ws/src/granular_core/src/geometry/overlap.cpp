#include "granular_core/geometry/overlap.h"

#include <algorithm>
#include <cmath>

namespace granular {
namespace {

// Twice the signed area of the triangle o, a, b: positive when b lies left of o -> a.
double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

double polygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& p = polygon[i];
    const Eigen::Vector2d& q = polygon[(i + 1) % polygon.size()];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(twice) / 2.0;
}

}  // namespace

std::vector<Eigen::Vector2d> footprintCorners(const OrientedBox& box) {
  const double yaw = box.yaw();
  const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d across(-along.y(), along.x());
  const Eigen::Vector2d centre = box.centre().head<2>();
  const Eigen::Vector2d half_length = along * box.size().x() / 2.0;
  const Eigen::Vector2d half_width = across * box.size().y() / 2.0;
  return {centre - half_length - half_width, centre + half_length - half_width,
          centre + half_length + half_width, centre - half_length + half_width};
}

double convexOverlapArea(const std::vector<Eigen::Vector2d>& a,
                         const std::vector<Eigen::Vector2d>& b) {
  if (a.size() < 3 || b.size() < 3) {
    return 0.0;
  }
  // a clipped by each edge of b in turn: what stays is left of every edge.
  std::vector<Eigen::Vector2d> clipped = a;
  for (std::size_t e = 0; e < b.size() && !clipped.empty(); ++e) {
    const Eigen::Vector2d& from = b[e];
    const Eigen::Vector2d& to = b[(e + 1) % b.size()];
    std::vector<Eigen::Vector2d> kept;
    for (std::size_t i = 0; i < clipped.size(); ++i) {
      const Eigen::Vector2d& p = clipped[i];
      const Eigen::Vector2d& q = clipped[(i + 1) % clipped.size()];
      const double side_p = cross(from, to, p);
      const double side_q = cross(from, to, q);
      if (side_p >= 0.0) {
        kept.push_back(p);
      }
      if ((side_p >= 0.0) != (side_q >= 0.0)) {
        kept.push_back(p + (q - p) * (side_p / (side_p - side_q)));
      }
    }
    clipped = std::move(kept);
  }
  return clipped.size() < 3 ? 0.0 : polygonArea(clipped);
}

double birdEyeOverlap(const OrientedBox& a, const OrientedBox& b) {
  const double smaller =
      std::min(a.size().x() * a.size().y(), b.size().x() * b.size().y());
  const double shared = convexOverlapArea(footprintCorners(a), footprintCorners(b));
  return std::clamp(shared / smaller, 0.0, 1.0);
}

}  // namespace granular
