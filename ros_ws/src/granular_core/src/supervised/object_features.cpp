// The features of one object: mean/std, the point feature histograms (paper 001) and the
// registration fitness profile. (Over 400 lines: the histograms' speed rests on the private
// neighbourhood grid and structure-of-arrays layout beside them, which no other unit uses.)
#include "granular_core/supervised/object_features.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "granular_core/search/grid_cells.h"

namespace granular {
namespace {

std::vector<Eigen::Vector3f> finitePoints(const Cloud& cloud) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(cloud.size());
  for (const PointXYZIT& point : cloud.points) {
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      points.emplace_back(point.x, point.y, point.z);
    }
  }
  return points;
}

// The points of an object bucketed in cubic cells of `cell` metres, for the neighbourhood
// queries of every sample: an object's cloud is small, and a query touches a few cells.
class CellIndex {
 public:
  // The cells of a query, clamped to the grid: low[0..2] and high[0..2] (x y z), inclusive.
  using Box = std::array<int, 6>;

  CellIndex(const std::vector<Eigen::Vector3f>& points, double cell)
      : cell_(static_cast<float>(cell)) {
    low_ = points.front();
    Eigen::Vector3f high = points.front();
    for (const Eigen::Vector3f& p : points) {
      low_ = low_.cwiseMin(p);
      high = high.cwiseMax(p);
    }
    for (int axis = 0; axis < 3; ++axis) {
      size_[axis] = static_cast<int>((high[axis] - low_[axis]) / cell_) + 1;
    }
    std::vector<std::size_t> cell_of(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      cell_of[i] = index(coordinates(points[i]));
    }
    lists_ = sortIntoCells(cell_of, static_cast<std::size_t>(size_[0]) * size_[1] * size_[2]);
  }

  // The cells overlapping the box [centre - half, centre + half], clamped to the grid here
  // (forEachCell would clamp them too) so that two queries over the same cells compare equal
  // and share one gather.
  Box cellsNear(const Eigen::Vector3f& centre, const Eigen::Vector3f& half) const {
    const Eigen::Vector3i low = coordinates(centre - half);
    const Eigen::Vector3i high = coordinates(centre + half);
    Box box;
    for (int axis = 0; axis < 3; ++axis) {
      box[axis] = std::max(low[axis], 0);
      box[3 + axis] = std::min(high[axis], size_[axis] - 1);
    }
    return box;
  }

  // Calls visit(point index) for every point in the cells of `box`, cell by cell (x fastest).
  template <typename Visit>
  void forEachIn(const Box& box, Visit visit) const {
    forEachCell(&box[0], &box[3], size_, [&](std::size_t cell) {
      for (std::uint32_t k = lists_.start[cell]; k < lists_.start[cell + 1]; ++k) {
        visit(lists_.order[k]);
      }
    });
  }

 private:
  Eigen::Vector3i coordinates(const Eigen::Vector3f& point) const {
    Eigen::Vector3i c;
    for (int axis = 0; axis < 3; ++axis) {
      const float offset = std::floor((point[axis] - low_[axis]) / cell_);
      c[axis] = static_cast<int>(std::clamp(offset, -1.0f, static_cast<float>(size_[axis])));
    }
    return c;
  }
  std::size_t index(const Eigen::Vector3i& c) const { return cellIndex(c.data(), size_); }

  float cell_;
  Eigen::Vector3f low_;
  int size_[3] = {1, 1, 1};
  CellLists lists_;
};

// Points of an object in structure-of-arrays form, for loops the compiler vectorises.
struct PointColumns {
  std::vector<std::uint32_t> index;  // into the object's points
  std::vector<float> x, y, z;

  // x, y and z of the points `index` names.
  void fill(const std::vector<Eigen::Vector3f>& points) {
    x.resize(index.size());
    y.resize(index.size());
    z.resize(index.size());
    for (std::size_t j = 0; j < index.size(); ++j) {
      const Eigen::Vector3f& point = points[index[j]];
      x[j] = point.x();
      y[j] = point.y();
      z[j] = point.z();
    }
  }
};

// The bin of a value in [0, 1] (values outside are clamped to the end bins).
std::size_t binOf(double value, std::size_t bins) {
  const double scaled = std::floor(value * static_cast<double>(bins));
  return static_cast<std::size_t>(std::clamp(scaled, 0.0, static_cast<double>(bins - 1)));
}

// The mean of `points` (at least one), summed in double.
Eigen::Vector3d meanOf(const std::vector<Eigen::Vector3f>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : points) {
    sum += p.cast<double>();
  }
  return sum / static_cast<double>(points.size());
}

// Shells of a quarter, a half and three quarters of neighbour_radius, in which a sample's
// nearest points are looked for before the whole sphere.
constexpr std::size_t kShells = 3;

}  // namespace

std::size_t featureSize(FeatureKind kind, const PointHistogramConfig& config) {
  switch (kind) {
    case FeatureKind::kMeanStd:
      return 6;
    case FeatureKind::kPointHistograms:
      return 4 + (3 + config.cylinder_slices) * config.bins;
    case FeatureKind::kEsf:
      return 640;
    case FeatureKind::kRegistrationFitness:
      return 0;
  }
  return 0;
}

std::array<double, 3> lalondeFeatures(const std::vector<Eigen::Vector3f>& points,
                                      ScatterDefinition scatter) {
  if (points.size() < 3) {
    return {0.0, 0.0, 0.0};
  }
  const Eigen::Vector3d mean = meanOf(points);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3d d = p.cast<double>() - mean;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(points.size());
  // Ascending eigenvalues of a positive semi-definite matrix; rounding may leave tiny negatives.
  // The closed form for 3x3 (Eigen's computeDirect), five times faster than the iterative
  // solver: this runs at every sample of every object.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ascending = solver.eigenvalues().cwiseMax(0.0);
  const double sum = ascending.sum();
  if (!(sum > 0.0)) {
    return {0.0, 0.0, 0.0};
  }
  const double d1 = ascending[2] / sum, d2 = ascending[1] / sum, d3 = ascending[0] / sum;
  return {scatter == ScatterDefinition::kSmallest ? d3 : d1, d1 - d2, d2 - d3};
}

std::vector<float> meanStdFeatures(const Cloud& object) {
  const std::vector<Eigen::Vector3f> points = finitePoints(object);
  std::vector<float> features(6, 0.0f);
  if (points.empty()) {
    return features;
  }
  const Eigen::Vector3d mean = meanOf(points);
  Eigen::Vector3d variance = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : points) {
    variance += (p.cast<double>() - mean).cwiseAbs2();
  }
  variance /= static_cast<double>(points.size());
  for (int axis = 0; axis < 3; ++axis) {
    features[axis] = static_cast<float>(mean[axis]);
    features[3 + axis] = static_cast<float>(std::sqrt(variance[axis]));
  }
  return features;
}

std::vector<float> pointHistogramFeatures(const Cloud& object,
                                          const PointHistogramConfig& config) {
  validate(config);
  const std::size_t bins = config.bins;
  const std::size_t slices = config.cylinder_slices;
  std::vector<float> features(featureSize(FeatureKind::kPointHistograms, config), 0.0f);

  // Object level: intensity over the finite points, and the volume of their box.
  std::vector<Eigen::Vector3f> points;
  std::vector<double> intensities;
  for (const PointXYZIT& point : object.points) {
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      points.emplace_back(point.x, point.y, point.z);
      intensities.push_back(point.intensity);
    }
  }
  if (points.empty()) {
    return features;
  }
  const double mean_intensity =
      std::accumulate(intensities.begin(), intensities.end(), 0.0) / intensities.size();
  double variance = 0.0;
  for (const double intensity : intensities) {
    variance += (intensity - mean_intensity) * (intensity - mean_intensity);
  }
  Eigen::Vector3f low = points.front(), high = points.front();
  for (const Eigen::Vector3f& p : points) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  features[0] = static_cast<float>(*std::max_element(intensities.begin(), intensities.end()));
  features[1] = static_cast<float>(mean_intensity);
  features[2] = static_cast<float>(variance / intensities.size());
  features[3] = (high - low).prod();

  // Uniform down-sampling: a repeatable random subset of `sample_points` points.
  std::vector<std::uint32_t> samples(points.size());
  std::iota(samples.begin(), samples.end(), 0u);
  if (samples.size() > config.sample_points) {
    std::mt19937 random(config.seed);
    for (std::size_t i = 0; i < config.sample_points; ++i) {
      std::uniform_int_distribution<std::size_t> pick(i, samples.size() - 1);
      std::swap(samples[i], samples[pick(random)]);
    }
    samples.resize(config.sample_points);
  }

  const float radius = static_cast<float>(config.neighbour_radius);
  const float cylinder_radius = static_cast<float>(config.cylinder_radius);
  const float half_height = static_cast<float>(config.cylinder_height / 2.0);
  const CellIndex cells(points, std::max(config.neighbour_radius, config.cylinder_radius));
  const float share = 1.0f / static_cast<float>(samples.size());
  const std::array<float, kShells> shells = {radius * radius / 16.0f, radius * radius / 4.0f,
                                             radius * radius * 9.0f / 16.0f};  // squared
  float* const lalonde_histograms = &features[4];
  float* const slice_histograms = &features[4 + 3 * bins];

  // Samples whose queries cover the same cells share their candidate points: gathered once per
  // group, in the order the cells are visited, so that every sample sees its candidates in the
  // same order as a query of its own would give them (the covariance sums depend on it).
  const Eigen::Vector3f reach(std::max(radius, cylinder_radius), std::max(radius, cylinder_radius),
                              std::max(radius, half_height));
  std::vector<std::pair<CellIndex::Box, std::uint32_t>> queries;
  queries.reserve(samples.size());
  for (const std::uint32_t sample : samples) {
    queries.emplace_back(cells.cellsNear(points[sample], reach), sample);
  }
  std::sort(queries.begin(), queries.end());

  PointColumns candidates;
  std::vector<float> squared;
  std::vector<std::int32_t> in_cylinder;  // 0 or 1, as wide as a float: vectorised
  // (squared distance, point index) as one number: a non-negative float's bits order as the
  // float does, so these order as the pairs do, and compare in one instruction.
  std::vector<std::uint64_t> near;
  std::vector<std::uint32_t> cylinder;
  std::vector<Eigen::Vector3f> neighbourhood;
  std::vector<std::size_t> slice_counts(slices);
  for (std::size_t first = 0; first < queries.size();) {
    std::size_t last = first;
    while (last < queries.size() && queries[last].first == queries[first].first) {
      ++last;
    }
    candidates.index.clear();
    cells.forEachIn(queries[first].first,
                    [&](std::uint32_t k) { candidates.index.push_back(k); });
    candidates.fill(points);
    const std::size_t count = candidates.index.size();
    squared.resize(count);
    in_cylinder.resize(count);
    near.resize(count);
    cylinder.resize(count);
    for (; first < last; ++first) {
      const Eigen::Vector3f& centre = points[queries[first].second];
      // Each candidate's squared distance and squared distance in x-y, as Eigen's
      // (p - centre).squaredNorm() and .head<2>().squaredNorm() compute them (Eigen sums three
      // values as x0 + (x1 + x2)), whether it lies in the cylinder, and how many lie within
      // each of the shells: one loop without branches, which the compiler vectorises.
      std::array<std::int32_t, kShells> within{};
      {
        const float* __restrict x = candidates.x.data();
        const float* __restrict y = candidates.y.data();
        const float* __restrict z = candidates.z.data();
        float* __restrict distance = squared.data();
        std::int32_t* __restrict column = in_cylinder.data();
        const float cx = centre.x(), cy = centre.y(), cz = centre.z();
        std::int32_t within0 = 0, within1 = 0, within2 = 0;
        for (std::size_t j = 0; j < count; ++j) {
          const float dx = x[j] - cx, dy = y[j] - cy, dz = z[j] - cz;
          distance[j] = dx * dx + (dy * dy + dz * dz);
          within0 += distance[j] <= shells[0];
          within1 += distance[j] <= shells[1];
          within2 += distance[j] <= shells[2];
          column[j] = (dx * dx + dy * dy <= cylinder_radius * cylinder_radius) &
                      (std::abs(dz) <= half_height);
        }
        within = {within0, within1, within2};
      }
      // The `neighbours` nearest within the radius lie within the smallest shell that holds that
      // many (or else the sphere): only the points within it are ranked, which on a dense car is
      // a fraction of its sphere's. The same points are kept; the covariance may sum them in
      // another order, a difference in the last bits (on the demo's test objects and crowded
      // frames no feature value changed).
      float bound = radius * radius;
      for (std::size_t shell = 0; shell < kShells; ++shell) {
        if (static_cast<std::size_t>(within[shell]) >= config.neighbours) {
          bound = shells[shell];
          break;
        }
      }
      // Those in each, in the candidates' order, without a branch per candidate.
      std::size_t near_count = 0, cylinder_count = 0;
      for (std::size_t j = 0; j < count; ++j) {
        std::uint32_t bits;
        std::memcpy(&bits, &squared[j], sizeof bits);
        near[near_count] = static_cast<std::uint64_t>(bits) << 32 | candidates.index[j];
        near_count += squared[j] <= bound;
        cylinder[cylinder_count] = static_cast<std::uint32_t>(j);
        cylinder_count += in_cylinder[j];
      }
      std::fill(slice_counts.begin(), slice_counts.end(), 0);
      for (std::size_t c = 0; c < cylinder_count; ++c) {
        const float dz = candidates.z[cylinder[c]] - centre.z();
        const double height = (dz + half_height) / (2.0 * half_height);
        ++slice_counts[binOf(height, slices)];
      }
      // The `neighbours` nearest within the radius (the sample itself among them). The keys are
      // distinct, so the set is the same whatever order the candidates come in; the order
      // nth_element leaves them in (the covariance's sums follow it) depends on that order too.
      const std::size_t kept = std::min(near_count, config.neighbours);
      if (kept < near_count) {
        std::nth_element(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(kept),
                         near.begin() + static_cast<std::ptrdiff_t>(near_count));
      }
      if (kept >= 3) {
        neighbourhood.clear();
        for (std::size_t n = 0; n < kept; ++n) {
          neighbourhood.push_back(points[static_cast<std::uint32_t>(near[n])]);
        }
        const std::array<double, 3> lalonde = lalondeFeatures(neighbourhood, config.scatter);
        for (std::size_t f = 0; f < 3; ++f) {
          lalonde_histograms[f * bins + binOf(lalonde[f], bins)] += share;
        }
      }
      // The sample itself is always in its cylinder, so cylinder_count >= 1.
      for (std::size_t slice = 0; slice < slices; ++slice) {
        const double fraction = static_cast<double>(slice_counts[slice]) / cylinder_count;
        slice_histograms[slice * bins + binOf(fraction, bins)] += share;
      }
    }
  }
  return features;
}

std::vector<float> objectFeatures(const Cloud& object, FeatureKind kind,
                                  const PointHistogramConfig& config) {
  switch (kind) {
    case FeatureKind::kMeanStd:
      return meanStdFeatures(object);
    case FeatureKind::kPointHistograms:
      return pointHistogramFeatures(object, config);
    case FeatureKind::kEsf:
      return esfFeatures(object);
    case FeatureKind::kRegistrationFitness:
      throw std::invalid_argument(
          "registration fitness features come from registering the object against the class "
          "models (classify_registration), not from its cloud alone");
  }
  throw std::invalid_argument("unknown feature kind");
}

std::vector<std::string> pointHistogramFeatureNames(const PointHistogramConfig& config) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < featureSize(FeatureKind::kPointHistograms, config); ++i) {
    names.push_back("point_histograms:" + std::to_string(i));
  }
  return names;
}

std::vector<float> registrationFitnessFeatures(const std::vector<std::vector<PairFitness>>& pairs,
                                               std::size_t points, bool inlier_shares) {
  std::vector<float> features;
  for (const std::vector<PairFitness>& per_model : pairs) {
    for (const PairFitness& pair : per_model) {
      const std::optional<double>& value = pair.fitness;
      const double known =
          value && std::isfinite(*value) ? std::clamp(*value, kFitnessFloor, kUnregisteredFitness)
                                         : kUnregisteredFitness;
      features.push_back(static_cast<float>(std::log(known)));
    }
  }
  features.push_back(static_cast<float>(std::log(std::max<std::size_t>(points, 1))));
  if (inlier_shares) {
    for (const std::vector<PairFitness>& per_model : pairs) {
      for (const PairFitness& pair : per_model) {
        for (const float share : pair.inlier_shares) {
          features.push_back(static_cast<float>(std::log((share + 0.01) / (1.01 - share))));
        }
      }
    }
  }
  return features;
}

}  // namespace granular
