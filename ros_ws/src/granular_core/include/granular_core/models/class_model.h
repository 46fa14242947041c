#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "granular_core/models/filter_chain.h"
#include "granular_core/models/model_config.h"
#include "granular_core/point_types.h"

namespace granular {

/// What building one class model did.
struct ClassModelSummary {
  std::string label;
  std::size_t objects = 0;  ///< object clouds of the class
  /// Objects in the raw model: all of them for plain concatenation; for ICP the seed objects
  /// plus the objects whose alignment was kept.
  std::size_t kept = 0;
  /// ICP only: "auto" (SeedConfig) or the seed PCD given for the class.
  std::string seed_source;
  std::vector<std::size_t> seed_objects;  ///< ICP, auto seed: indices into the class's objects
  std::vector<std::string> missing_sides; ///< ICP, auto seed: sides no object shows
  std::size_t seed_points = 0;            ///< ICP: points of the seed
  std::map<std::string, std::size_t> verdicts;     ///< ICP: objects per verdictName
  std::map<std::string, std::size_t> convergence;  ///< ICP: aligned objects per convergenceName
  std::size_t raw_points = 0;
  /// The chain used (shared chain with class overrides, an automatic max_z worked out).
  FilterChainConfig filters;
  std::vector<StageResult> stages;  ///< points after each stage
  std::size_t points = 0;           ///< points of the filtered model
  /// The filter stage that left no points, when the model is empty though objects were there.
  std::optional<FilterStage> emptied_by;
  std::size_t mesh_polygons = 0;    ///< with a mesh
  double seconds = 0.0;             ///< wall time of concatenation and filtering
  std::vector<std::string> warnings;
};

/// A class model: its raw (concatenated) and filtered clouds.
struct ClassModel {
  ClassModelSummary summary;
  ModelCloud raw;
  ModelCloud model;
};

/// Builds the model of class `label` from its object clouds: concatenation by config.method,
/// then config.filtersFor(label). For ICP, `seed` is the starting model when given; otherwise
/// the seed is selected by selectSeedObjects; the seed's points stay in the model. No objects
/// give an empty model, no stages and a warning; for ICP a single object is its own model (with
/// a warning). `progress`, when set, is called
/// with (objects aligned, objects to align) during ICP.
/// `box_heights` (m, the class's detection boxes' heights, from the objects folder's index)
/// set an automatic pass_through.max_z (autoMaxZ); without them it follows the objects' own
/// highest points the same way.
ClassModel buildClassModel(const std::string& label, const std::vector<ModelCloud>& objects,
                           const ModelBuildConfig& config, const ModelCloud* seed = nullptr,
                           const std::function<void(std::size_t, std::size_t)>& progress = {},
                           const std::vector<double>& box_heights = {});

}  // namespace granular
