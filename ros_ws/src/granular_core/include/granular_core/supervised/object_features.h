#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "granular_core/config/fields.h"
#include "granular_core/point_types.h"
#include "granular_core/search/inlier_shares.h"

namespace granular {

/// The feature vectors of the supervised classifiers, computed from an object's cloud in its
/// own frame (origin at the centre of the box's bottom face, x forward, y left, z up), or, for
/// kRegistrationFitness, from its registration against the class models.
enum class FeatureKind {
  kMeanStd,         ///< report 8.4: [mu_x, mu_y, mu_z, sigma_x, sigma_y, sigma_z]
  kPointHistograms, ///< paper 001, III: 4 object-level values and 8 histograms of b bins
  kEsf,             ///< PCL's Ensemble of Shape Functions, 640 values
  /// The log of the object's fitness against every class model under one or more
  /// registration methods, and the log of its point count (registrationFitnessFeatures);
  /// as many values as the classifier's feature names. Not computed from a cloud alone.
  kRegistrationFitness,
};

template <>
struct config::EnumNames<FeatureKind> {
  static constexpr const char* what = "feature kind";
  static constexpr std::array<std::pair<FeatureKind, const char*>, 4> values{
      {{FeatureKind::kMeanStd, "mean_std"},
       {FeatureKind::kPointHistograms, "point_histograms"},
       {FeatureKind::kEsf, "esf"},
       {FeatureKind::kRegistrationFitness, "registration_fitness"}}};
};

/// "mean_std", "point_histograms", "esf" or "registration_fitness".
inline const char* featureKindName(FeatureKind kind) { return config::enumName(kind); }
inline std::optional<FeatureKind> featureKindFromName(const std::string& name) {
  return config::enumFromName<FeatureKind>(name);
}

/// Which sum-normalised eigenvalue (d1 >= d2 >= d3) the scatter-ness L1 is.
enum class ScatterDefinition {
  /// d3, as Lalonde et al. define scatter-ness: it is large only where the neighbourhood spreads
  /// in all three directions (1/3 for an isotropic blob, 0 on a plane or a line).
  kSmallest,
  /// d1, as the paper's text writes it (L1 = d1): the largest spread, 1 on a line, 1/2 on a
  /// plane, 1/3 in a blob.
  kLargest,
};

template <>
struct config::EnumNames<ScatterDefinition> {
  static constexpr const char* what = "scatter definition";
  static constexpr std::array<std::pair<ScatterDefinition, const char*>, 2> values{
      {{ScatterDefinition::kSmallest, "smallest"}, {ScatterDefinition::kLargest, "largest"}}};
};

inline const char* scatterDefinitionName(ScatterDefinition definition) {
  return config::enumName(definition);
}
inline std::optional<ScatterDefinition> scatterDefinitionFromName(const std::string& name) {
  return config::enumFromName<ScatterDefinition>(name);
}

/// The point feature histograms of the paper (Himmelsbach et al., section III). The object is
/// uniformly sampled down to `sample_points` points; at each sample, features of its
/// neighbourhood in the whole object cloud:
///  - Lalonde: L1 (scatter, see `scatter`), L2 = d1 - d2 (linear), L3 = d2 - d3 (surface) from
///    the sorted, sum-normalised eigenvalues of the covariance of its `neighbours` nearest
///    points within `neighbour_radius` (fewer than 3 neighbours: no Lalonde values);
///  - Anguelov: the points of the whole cloud in the vertical cylinder of `cylinder_height` and
///    `cylinder_radius` centred on the sample, split into `cylinder_slices` equal slices from
///    bottom to top; each slice's fraction of them.
/// Each of the 3 + slices values gets a histogram of `bins` bins over [0, 1], divided by the
/// number of samples. Before them, 4 object-level values: the maximum, mean and variance of the
/// intensity (0 for a cloud without intensity) and the volume of the object's points' box in
/// its frame. Default: 4 + 8 x 7 = 60 values.
struct PointHistogramConfig {
  std::size_t sample_points = 200;   ///< M
  std::size_t neighbours = 20;       ///< nearest points for the covariance
  double neighbour_radius = 0.5;     ///< m
  std::size_t bins = 7;              ///< b
  double cylinder_height = 1.0;      ///< m
  double cylinder_radius = 0.25;     ///< m
  std::size_t cylinder_slices = 5;
  ScatterDefinition scatter = ScatterDefinition::kSmallest;
  std::uint32_t seed = 1;            ///< of the down-sampling, so that features are repeatable

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("sample_points", self.sample_points, config::atLeast(1, "points"));
    // A covariance needs three points.
    visit("neighbours", self.neighbours, config::atLeast(3, "points"));
    visit("neighbour_radius", self.neighbour_radius, config::positive("m"));
    visit("bins", self.bins, config::atLeast(1));
    visit("cylinder_height", self.cylinder_height, config::positive("m"));
    visit("cylinder_radius", self.cylinder_radius, config::positive("m"));
    visit("cylinder_slices", self.cylinder_slices, config::atLeast(1));
    visit("scatter", self.scatter);
    visit("seed", self.seed);
  }
};

/// Throws std::invalid_argument naming the field for a value out of range.
inline void validate(const PointHistogramConfig& config) { config::validateFields(config); }

/// Values of a feature vector of `kind`; 0 for kRegistrationFitness, whose size is the number
/// of models and registration methods it was built from.
std::size_t featureSize(FeatureKind kind, const PointHistogramConfig& config);

/// L1, L2, L3 of the sorted, sum-normalised eigenvalues d1 >= d2 >= d3 of a covariance matrix
/// of `points` (x y z each); all 0 for fewer than 3 points or no spread.
std::array<double, 3> lalondeFeatures(const std::vector<Eigen::Vector3f>& points,
                                      ScatterDefinition scatter);

/// The feature vector of `kind` for one object cloud; never NaN: an empty cloud gives zeros,
/// non-finite points are ignored. Throws std::invalid_argument for kRegistrationFitness, which
/// a cloud alone does not give.
std::vector<float> objectFeatures(const Cloud& object, FeatureKind kind,
                                  const PointHistogramConfig& config = {});

/// Report 8.4: mean and (population) standard deviation of x, y and z.
std::vector<float> meanStdFeatures(const Cloud& object);

/// Paper III: the 4 + (3 + slices) x bins values described at PointHistogramConfig.
std::vector<float> pointHistogramFeatures(const Cloud& object, const PointHistogramConfig& config);

/// Names of the point histogram values when they follow another classifier's features
/// (svm_fitness): "point_histograms:0" to "point_histograms:<featureSize - 1>".
std::vector<std::string> pointHistogramFeatureNames(const PointHistogramConfig& config);

/// A pair's fitness (m^2) when registration gave none (it failed, or the object had too few
/// points): worse than any registered object's, so the pair looks like a bad match.
constexpr double kUnregisteredFitness = 100.0;
/// Below this (m^2, a millimetre's RMS) fitness values are taken as equal: the log stays finite.
constexpr double kFitnessFloor = 1e-6;

/// What svm_fitness reads of one object's registration against one class model, as
/// classify_registration's results record it.
struct PairFitness {
  std::optional<double> fitness;  ///< m^2; none: not registered, or no finite fitness
  InlierShares inlier_shares{};   ///< zeros where the fitness is none
};

/// kRegistrationFitness: for each registration method in turn, the natural log of the
/// object's fitness against each class model (`pairs[method][model]`, m^2, clamped to
/// [kFitnessFloor, kUnregisteredFitness]; none or non-finite is kUnregisteredFitness), then
/// the log of its point count (at least 1), then with `inlier_shares` for each method, model
/// and radius in turn the log-odds of the inlier share s, log((s + 0.01) / (1.01 - s)), which
/// spreads the shares near 0 and 1 where a close model and a closer one differ. A Hatchback's
/// fitness against the Sedan model is nearly its fitness against its own: the whole profile
/// over the models, with how sparse the object is, tells them apart better than the lowest
/// value alone.
std::vector<float> registrationFitnessFeatures(const std::vector<std::vector<PairFitness>>& pairs,
                                               std::size_t points, bool inlier_shares);

/// pcl::ESFEstimation's 640 values, summing to 1, from the finite points (zeros for fewer
/// than 3). PCL seeds its sampling with the time in seconds: two calls may differ.
std::vector<float> esfFeatures(const Cloud& object);

}  // namespace granular
