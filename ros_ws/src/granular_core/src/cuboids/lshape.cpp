#include "granular_core/cuboids/lshape.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

namespace granular {
namespace {

constexpr double kQuarterTurn = M_PI / 2;

// A direction modulo 90 degrees, in [0, pi/2): a rectangle is the same turned a quarter.
double quarterAngle(double theta) {
  theta = std::fmod(theta, kQuarterTurn);
  return theta < 0.0 ? theta + kQuarterTurn : theta;
}

// Scores directions for one set of points, reusing its buffers.
class Scorer {
 public:
  Scorer(const std::vector<Eigen::Vector2d>& points, const LShapeConfig& config)
      : points_(points), config_(config), c1_(points.size()), c2_(points.size()) {}

  double operator()(double theta) { return (*this)(std::cos(theta), std::sin(theta)); }

  // The score of the direction whose cosine and sine these are.
  double operator()(double cos_t, double sin_t) {
    double min1 = std::numeric_limits<double>::infinity(), max1 = -min1;
    double min2 = min1, max2 = -min1;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      c1_[i] = points_[i].x() * cos_t + points_[i].y() * sin_t;
      c2_[i] = -points_[i].x() * sin_t + points_[i].y() * cos_t;
      min1 = std::min(min1, c1_[i]);
      max1 = std::max(max1, c1_[i]);
      min2 = std::min(min2, c2_[i]);
      max2 = std::max(max2, c2_[i]);
    }
    if (config_.criterion == LShapeCriterion::kArea) {
      return -(max1 - min1) * (max2 - min2);
    }
    // Each axis's nearer edge: the one whose distances to all the points are the smaller
    // vector (the paper's argmin over the two candidate vectors).
    const bool near_max1 = nearerToHigh(c1_, min1, max1);
    const bool near_max2 = nearerToHigh(c2_, min2, max2);
    double closeness = 0.0;
    Moments e1, e2;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const double d1 = near_max1 ? max1 - c1_[i] : c1_[i] - min1;
      const double d2 = near_max2 ? max2 - c2_[i] : c2_[i] - min2;
      if (config_.criterion == LShapeCriterion::kCloseness) {
        closeness += 1.0 / std::max(std::min(d1, d2), config_.closeness_d0);
      } else if (d1 < d2) {
        e1.add(d1);
      } else if (d2 < d1) {
        e2.add(d2);
      }
    }
    if (config_.criterion == LShapeCriterion::kCloseness) {
      return closeness;
    }
    return -e1.variance() - e2.variance();
  }

 private:
  struct Moments {
    double n = 0.0, sum = 0.0, sum_squares = 0.0;
    void add(double value) {
      n += 1.0;
      sum += value;
      sum_squares += value * value;
    }
    double variance() const {
      return n > 0.0 ? std::max(0.0, sum_squares / n - (sum / n) * (sum / n)) : 0.0;
    }
  };

  // Whether the squared distances of `values` to `high` sum to less than those to `low`: both
  // sums in one pass, each in the values' order.
  static bool nearerToHigh(const std::vector<double>& values, double low, double high) {
    double to_high = 0.0, to_low = 0.0;
    for (const double value : values) {
      to_high += (high - value) * (high - value);
      to_low += (low - value) * (low - value);
    }
    return to_high < to_low;
  }

  const std::vector<Eigen::Vector2d>& points_;
  const LShapeConfig& config_;
  std::vector<double> c1_, c2_;
};

// The cosines and sines of k * step for k below `steps`: every object's coarse search turns
// through the same directions, and computing them was a third of the search's instructions.
// Per thread, for the step last asked.
const std::vector<std::pair<double, double>>& coarseDirections(double step, int steps) {
  thread_local std::vector<std::pair<double, double>> directions;
  thread_local double directions_step = 0.0;
  if (directions_step != step || directions.size() != static_cast<std::size_t>(steps)) {
    directions.clear();
    for (int k = 0; k < steps; ++k) {
      const double theta = k * step;
      directions.emplace_back(std::cos(theta), std::sin(theta));
    }
    directions_step = step;
  }
  return directions;
}

}  // namespace

Eigen::Vector2d AxisRectangle::u() const { return {std::cos(heading), std::sin(heading)}; }

Eigen::Vector2d AxisRectangle::v() const { return {-std::sin(heading), std::cos(heading)}; }

Eigen::Vector2d AxisRectangle::centre() const {
  const Eigen::Vector2d middle = (min + max) / 2;
  return u() * middle.x() + v() * middle.y();
}

Eigen::Vector2d AxisRectangle::coordinates(const Eigen::Vector2d& point) const {
  return RectangleAxes(*this).coordinates(point);
}

Eigen::Vector2d AxisRectangle::point(const Eigen::Vector2d& coordinates) const {
  return u() * coordinates.x() + v() * coordinates.y();
}

std::vector<Eigen::Vector2d> thinnedPoints(const std::vector<Eigen::Vector2d>& points,
                                           double cell) {
  if (!(cell > 0.0)) {
    throw std::invalid_argument("thinnedPoints: the cell must be positive");
  }
  // Cell keys sorted with the point's index; runs of one key are one cell.
  std::vector<std::pair<std::uint64_t, std::size_t>> keys;
  keys.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto column = static_cast<std::int64_t>(std::floor(points[i].x() / cell));
    const auto row = static_cast<std::int64_t>(std::floor(points[i].y() / cell));
    const std::uint64_t key = (static_cast<std::uint64_t>(column) << 32) ^
                              (static_cast<std::uint64_t>(row) & 0xffffffffULL);
    keys.emplace_back(key, i);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<Eigen::Vector2d> thinned;
  for (std::size_t start = 0; start < keys.size();) {
    std::size_t end = start;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (; end < keys.size() && keys[end].first == keys[start].first; ++end) {
      sum += points[keys[end].second];
    }
    thinned.push_back(sum / static_cast<double>(end - start));
    start = end;
  }
  return thinned;
}

double lshapeScore(const std::vector<Eigen::Vector2d>& points, double theta,
                   const LShapeConfig& config) {
  return Scorer(points, config)(theta);
}

AxisRectangle fitLShape(const std::vector<Eigen::Vector2d>& points, const LShapeConfig& config) {
  if (points.empty()) {
    throw std::invalid_argument("fitLShape: no points");
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& point : points) {
    mean += point;
  }
  mean /= static_cast<double>(points.size());
  std::vector<Eigen::Vector2d> centred;
  centred.reserve(points.size());
  for (const Eigen::Vector2d& point : points) {
    centred.push_back(point - mean);
  }
  Scorer score(centred, config);
  const double coarse = config.coarse_step_deg * M_PI / 180.0;
  const double fine = config.fine_step_deg * M_PI / 180.0;
  double best = 0.0, best_score = -std::numeric_limits<double>::infinity();
  const int coarse_steps = static_cast<int>(std::ceil(kQuarterTurn / coarse - 1e-9));
  const std::vector<std::pair<double, double>>& directions =
      coarseDirections(coarse, coarse_steps);
  for (int k = 0; k < coarse_steps; ++k) {
    const auto& [cos_t, sin_t] = directions[static_cast<std::size_t>(k)];
    const double value = score(cos_t, sin_t);
    if (value > best_score) {
      best_score = value;
      best = k * coarse;
    }
  }
  const double centre = best;
  const int fine_steps = static_cast<int>(std::floor(coarse / fine + 1e-9));
  for (int k = -fine_steps; k <= fine_steps; ++k) {
    const double theta = centre + k * fine;
    const double value = score(theta);
    if (value > best_score) {
      best_score = value;
      best = theta;
    }
  }

  AxisRectangle rectangle;
  rectangle.heading = quarterAngle(best);
  rectangle.min.setConstant(std::numeric_limits<double>::infinity());
  rectangle.max.setConstant(-std::numeric_limits<double>::infinity());
  const RectangleAxes axes(rectangle);
  for (const Eigen::Vector2d& point : points) {
    const Eigen::Vector2d c = axes.coordinates(point);
    rectangle.min = rectangle.min.cwiseMin(c);
    rectangle.max = rectangle.max.cwiseMax(c);
  }
  return rectangle;
}

}  // namespace granular
