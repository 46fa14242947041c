#include "granular_core/geometry/footprint.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace granular {
namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// An angle in (-pi/2, pi/2]: a rectangle's axis has no front.
double axisAngle(double angle) {
  while (angle > M_PI / 2) {
    angle -= M_PI;
  }
  while (angle <= -M_PI / 2) {
    angle += M_PI;
  }
  return angle;
}

// `points` without those strictly inside the polygon of their extremes in eight directions
// (Akl and Toussaint): none of them is a hull corner, and a segment's footprint of thousands of
// returns keeps a few hundred to sort.
void dropInterior(std::vector<Eigen::Vector2d>& points) {
  // The extremes in directions 45 degrees apart, counter-clockwise from straight down: (0, -1),
  // (1, -1), (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1). Their dot products with a point
  // are sums and differences of its coordinates, exactly.
  if (points.size() < 3) {
    return;
  }
  std::array<std::size_t, 8> extreme{};
  std::array<double, 8> best;
  best.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double x = points[i].x(), y = points[i].y();
    const std::array<double, 8> reach = {-y, x - y, x, x + y, y, y - x, -x, -x - y};
    for (std::size_t d = 0; d < 8; ++d) {
      if (reach[d] > best[d]) {
        best[d] = reach[d];
        extreme[d] = i;
      }
    }
  }
  std::vector<Eigen::Vector2d> corners;
  for (const std::size_t index : extreme) {
    if (corners.empty() || points[index] != corners.back()) {
      corners.push_back(points[index]);
    }
  }
  while (corners.size() > 1 && corners.back() == corners.front()) {
    corners.pop_back();
  }
  if (corners.size() < 3) {
    return;
  }
  // Each side of the polygon: its first corner and its direction to the next.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> sides;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    sides.emplace_back(corners[i], corners[(i + 1) % corners.size()] - corners[i]);
  }
  const auto inside = [&](const Eigen::Vector2d& p) {
    for (const auto& [from, along] : sides) {
      // cross(from, from + along, p), as cross() computes it.
      if (along.x() * (p.y() - from.y()) - along.y() * (p.x() - from.x()) <= 0.0) {
        return false;
      }
    }
    return true;
  };
  points.erase(std::remove_if(points.begin(), points.end(), inside), points.end());
}

}  // namespace

std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> points) {
  dropInterior(points);
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) {
    return points;
  }
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const Eigen::Vector2d& p : points) {  // lower hull
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) {
      --k;
    }
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) {
      --k;
    }
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

Rectangle minimumAreaRectangle(const std::vector<Eigen::Vector2d>& points) {
  Rectangle best;
  if (points.empty()) {
    return best;
  }
  const std::vector<Eigen::Vector2d> hull = convexHull(points);
  // Candidate directions: each hull edge (one is a side of the best rectangle); the x axis for
  // degenerate hulls.
  // A closed hull has as many edges as corners; two points have one edge, one point none.
  const std::size_t edges = hull.size() >= 3 ? hull.size() : hull.size() - 1;
  std::vector<double> angles;
  for (std::size_t i = 0; i < edges; ++i) {
    const Eigen::Vector2d edge = hull[(i + 1) % hull.size()] - hull[i];
    if (edge.squaredNorm() > 0.0) {
      angles.push_back(std::atan2(edge.y(), edge.x()));
    }
  }
  if (angles.empty()) {
    angles.push_back(0.0);
  }
  double best_area = std::numeric_limits<double>::infinity();
  for (const double angle : angles) {
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    const Eigen::Vector2d v(-u.y(), u.x());
    double min_u = std::numeric_limits<double>::infinity(), max_u = -min_u;
    double min_v = min_u, max_v = -min_u;
    for (const Eigen::Vector2d& p : hull) {
      min_u = std::min(min_u, p.dot(u));
      max_u = std::max(max_u, p.dot(u));
      min_v = std::min(min_v, p.dot(v));
      max_v = std::max(max_v, p.dot(v));
    }
    const double area = (max_u - min_u) * (max_v - min_v);
    if (area < best_area) {
      best_area = area;
      best.centre = u * (min_u + max_u) / 2 + v * (min_v + max_v) / 2;
      const double along_u = max_u - min_u, along_v = max_v - min_v;
      if (along_u >= along_v) {
        best.length = along_u;
        best.width = along_v;
        best.yaw = axisAngle(angle);
      } else {
        best.length = along_v;
        best.width = along_u;
        best.yaw = axisAngle(angle + M_PI / 2);
      }
    }
  }
  return best;
}

}  // namespace granular
