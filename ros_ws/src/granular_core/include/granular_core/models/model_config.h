#pragma once

#include <array>
#include <cstddef>
#include <utility>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "granular_core/config/fields.h"

namespace granular {

/// How the objects of a class are stacked into its raw model (report 5.2).
enum class ConcatenationMethod {
  kPlain,  ///< 5.2.1: every object as extracted, in the shared object frame
  kIcp,    ///< 5.2.2: each object aligned to the growing model first, kept if ICP succeeded
};

template <>
struct config::EnumNames<ConcatenationMethod> {
  static constexpr const char* what = "method";
  static constexpr std::array<std::pair<ConcatenationMethod, const char*>, 2> values{
      {{ConcatenationMethod::kPlain, "plain"}, {ConcatenationMethod::kIcp, "icp"}}};
};

/// "plain" or "icp".
inline const char* methodName(ConcatenationMethod method) { return config::enumName(method); }
/// The method called `name`, or nullopt.
inline std::optional<ConcatenationMethod> methodFromName(const std::string& name) {
  return config::enumFromName<ConcatenationMethod>(name);
}

/// The stages of the model filter chain (report 5.3).
enum class FilterStage { kPassThrough, kRadiusOutlier, kStatisticalOutlier, kVoxelGrid };

template <>
struct config::EnumNames<FilterStage> {
  static constexpr const char* what = "stage";
  static constexpr std::array<std::pair<FilterStage, const char*>, 4> values{
      {{FilterStage::kPassThrough, "pass_through"},
       {FilterStage::kRadiusOutlier, "radius_outlier"},
       {FilterStage::kStatisticalOutlier, "statistical_outlier"},
       {FilterStage::kVoxelGrid, "voxel_grid"}}};
};

/// "pass_through", "radius_outlier", "statistical_outlier" or "voxel_grid".
inline const char* stageName(FilterStage stage) { return config::enumName(stage); }
/// The stage called `name`, or nullopt.
inline std::optional<FilterStage> stageFromName(const std::string& name) {
  return config::enumFromName<FilterStage>(name);
}

/// 5.3.1 ground removal: keeps the points with min_z <= z <= max_z (both inclusive). Object
/// frame: z = 0 is the bottom face of the detection box, i.e. the road.
struct PassThroughConfig {
  double min_z = 0.2;  ///< m
  /// m; unset ("auto"): kAutoMaxZFactor times the 95th percentile of the class's box heights,
  /// so that tall classes (buses, trucks) keep their tops and a few oversized boxes do not
  /// set the band (autoMaxZ).
  std::optional<double> max_z;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("min_z", self.min_z, config::any("m"));
    visit("max_z", self.max_z, config::automatic("m"));
  }
};

/// The margin of an automatic max_z over the 95th percentile of the box heights: real classes
/// vary in height by a few per cent (the simulator's by up to 4%).
inline constexpr double kAutoMaxZFactor = 1.05;

/// The automatic max_z of a class: kAutoMaxZFactor times the 95th percentile of `heights` (m,
/// its objects' box heights); nullopt for no heights.
std::optional<double> autoMaxZ(std::vector<double> heights);

/// 5.3.2: keeps the points with at least min_neighbors other points within radius.
struct RadiusOutlierConfig {
  double radius = 0.2;     ///< m
  int min_neighbors = 2;   ///< points, not counting the point itself

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("radius", self.radius, config::positive("m"));
    visit("min_neighbors", self.min_neighbors, config::atLeast(1, "points"));
  }
};

/// 5.3.3: removes the points whose mean distance to their mean_k nearest neighbours exceeds
/// mean + stddev_mul * standard deviation of that distance over the cloud.
struct StatisticalOutlierConfig {
  int mean_k = 5;            ///< neighbours
  double stddev_mul = 0.3;   ///< standard deviations

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("mean_k", self.mean_k, config::atLeast(1, "neighbours"));
    visit("stddev_mul", self.stddev_mul, config::any("standard deviations"));
  }
};

/// 5.3.4: replaces the points of each cubic voxel by their centroid.
struct VoxelGridConfig {
  double leaf_size = 0.1;  ///< m, edge of a voxel

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("leaf_size", self.leaf_size, config::positive("m"));
  }
};

/// The filter chain of a model: the stages in `order` run one after the other; a stage left
/// out of `order` does not run. The report's chain is pass-through, statistical outlier
/// removal and voxel grid; radius outlier removal is the fourth stage it describes.
struct FilterChainConfig {
  std::vector<FilterStage> order = {FilterStage::kPassThrough, FilterStage::kRadiusOutlier,
                                    FilterStage::kStatisticalOutlier, FilterStage::kVoxelGrid};
  PassThroughConfig pass_through;
  RadiusOutlierConfig radius_outlier;
  StatisticalOutlierConfig statistical_outlier;
  VoxelGridConfig voxel_grid;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("order", self.order);
    visit("pass_through", self.pass_through);
    visit("radius_outlier", self.radius_outlier);
    visit("statistical_outlier", self.statistical_outlier);
    visit("voxel_grid", self.voxel_grid);
  }
};

/// Per-class changes to the shared FilterChainConfig, in its layout: each value set replaces
/// the shared one for that class; the others follow the shared chain.
using FilterChainOverrides = config::Overrides<FilterChainConfig>;

/// ICP alignment of one object to the growing model (pcl::IterativeClosestPoint, point to
/// point, 6 degrees of freedom). An object is kept when all of these hold:
///  - ICP converged: its convergence state (DefaultConvergenceCriteria) is TRANSFORM (the last
///    step was below transformation_epsilon), ABS_MSE or REL_MSE (the mean squared error
///    stopped changing). Reaching max_iterations (state ITERATIONS, for which PCL's
///    hasConverged() is nonetheless true), finding no correspondences or not converging are
///    failures;
///  - the fitness, the mean squared distance of the aligned object's points to their nearest
///    model points, is at most max_fitness;
///  - the correction is at most max_translation and max_rotation_deg: the misplacement it is
///    there to repair (stamp offset between cloud and detection, times the relative speed) is
///    a few tens of centimetres, so a larger correction is a wrong match;
///  - the object has at least min_points points.
struct IcpConfig {
  int max_iterations = 100;
  double max_correspondence_distance = 0.5;   ///< m, point pairs farther apart are ignored
  double transformation_epsilon = 1e-6;       ///< m^2, squared translation of the last step
  double euclidean_fitness_epsilon = 1e-4;    ///< relative change of the mean squared error
  double max_fitness = 0.01;                  ///< m^2 (0.01 m^2 = 10 cm RMS)
  double max_translation = 0.5;               ///< m
  double max_rotation_deg = 10.0;             ///< deg
  std::size_t min_points = 10;                ///< points
  /// m; the ICP target is the growing model through a voxel grid of this leaf (0: the whole
  /// model), which bounds the cost of each alignment as the model grows.
  double target_leaf_size = 0.05;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("max_iterations", self.max_iterations, config::atLeast(1));
    visit("max_correspondence_distance", self.max_correspondence_distance, config::positive("m"));
    visit("transformation_epsilon", self.transformation_epsilon, config::nonNegative("m^2"));
    visit("euclidean_fitness_epsilon", self.euclidean_fitness_epsilon, config::nonNegative());
    visit("max_fitness", self.max_fitness, config::positive("m^2"));
    visit("max_translation", self.max_translation, config::positive("m"));
    visit("max_rotation_deg", self.max_rotation_deg, config::interval(0, 180, "deg", true));
    visit("min_points", self.min_points, config::atLeast(3, "points"));
    // 0: the whole model as target.
    visit("target_leaf_size", self.target_leaf_size, config::nonNegative("m"));
  }
};

/// The automatic ICP seed: for each side of the object (front, back, left, right) the
/// objects_per_side objects with most points that show that side, concatenated as they are
/// (the report hand-picked such objects). The side an object shows is the direction of the
/// centroid of its object-frame points, each axis scaled by the class's half extent on it.
struct SeedConfig {
  std::size_t objects_per_side = 2;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("objects_per_side", self.objects_per_side, config::atLeast(1, "objects"));
  }
};

/// Optional mesh (report section 6): normals from the normal_k nearest neighbours, then
/// pcl::GreedyProjectionTriangulation with the other values.
struct MeshConfig {
  int normal_k = 20;                      ///< neighbours
  double search_radius = 0.3;             ///< m, longest triangle edge
  double mu = 2.5;                        ///< multiplier of the nearest-neighbour distance
  int max_nearest_neighbors = 100;
  double max_surface_angle_deg = 45.0;    ///< deg
  double min_angle_deg = 10.0;            ///< deg, smallest triangle angle
  double max_angle_deg = 120.0;           ///< deg, largest triangle angle

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("normal_k", self.normal_k, config::atLeast(3, "neighbours"));
    visit("search_radius", self.search_radius, config::positive("m"));
    visit("mu", self.mu, config::positive());
    visit("max_nearest_neighbors", self.max_nearest_neighbors, config::atLeast(3));
    visit("max_surface_angle_deg", self.max_surface_angle_deg,
          config::interval(0, 180, "deg", true));
    visit("min_angle_deg", self.min_angle_deg, config::interval(0, 180, "deg", true, true));
    visit("max_angle_deg", self.max_angle_deg, config::interval(0, 180, "deg", true, true));
  }
};

/// The per-class overrides of the defaults (see ModelBuildConfig::class_filters).
FilterChainOverrides defaultClassFilters();

/// Every tunable of the models stage. The defaults here are the reference values (report 5.2
/// and 5.3); tools overlay a YAML file and command-line options on them.
struct ModelBuildConfig {
  /// The report's final models use plain concatenation: after filtering, ICP models were not
  /// better.
  ConcatenationMethod method = ConcatenationMethod::kPlain;
  IcpConfig icp;
  SeedConfig seed;
  FilterChainConfig filters;
  /// By class name. The shared chain holds the report's values (band from 0.2 m, K = 5,
  /// m = 0.3, leaf 0.1 m) but for the band's top, which follows each class's boxes (the
  /// report's 2.0 m cut the tops off buses and trucks). Each simulated vehicle class has its
  /// own leaf to land near the report's 5,000 points per model: with the report's 0.1 m the
  /// vehicle models of the simulated drive keep only 1,400-3,600 points.
  /// Pedestrians (about 1,600 points before the voxel grid) cannot reach 5,000 and keep the
  /// shared leaf.
  FilterChainOverrides class_filters = defaultClassFilters();
  MeshConfig mesh;
  /// A class gets a model only when it has at least min_objects objects and its filtered
  /// model at least min_points points; the others are left out with a warning (a real
  /// dataset's rare classes: a single tram, a few pylons the filters empty), and the run fails
  /// only when no class is left.
  std::size_t min_objects = 1;  ///< objects
  std::size_t min_points = 10;  ///< points of the filtered model

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("min_objects", self.min_objects, config::atLeast(1, "objects"));
    visit("min_points", self.min_points, config::atLeast(1, "points"));
    visit("method", self.method);
    visit("seed", self.seed);
    visit("icp", self.icp);
    visit("filters", self.filters);
    visit("class_filters", self.class_filters);
    visit("mesh", self.mesh);
  }

  /// The shared chain with the overrides of class `label`, if any.
  FilterChainConfig filtersFor(const std::string& label) const;
};

/// Throws std::invalid_argument naming the field (and the class, for an override) for a value
/// out of range: a band with min_z > max_z, a non-positive radius, leaf or distance, a
/// repeated stage, and so on.
void validate(const ModelBuildConfig& config);


}  // namespace granular
