#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "granular_core/point_types.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// How a registration ended: pcl::registration::DefaultConvergenceCriteria's state. Only
/// kTransform, kAbsMse and kRelMse count as converged (see IcpConfig).
enum class IcpConvergence {
  kNotConverged,
  kIterations,
  kTransform,
  kAbsMse,
  kRelMse,
  kNoCorrespondences,
  kFailureAfterMaxIterations,
};

/// "not_converged", "iterations", "transform", "abs_mse", "rel_mse", "no_correspondences" or
/// "failure_after_max_iterations".
const char* convergenceName(IcpConvergence convergence);

/// True for kTransform, kAbsMse and kRelMse.
bool isConverged(IcpConvergence convergence);

/// Why an object was or was not added to an ICP model, in the order the checks run.
enum class IcpVerdict { kKept, kTooFewPoints, kNotConverged, kPoorFitness, kLargeCorrection };

/// "kept", "too_few_points", "not_converged", "poor_fitness" or "large_correction".
const char* verdictName(IcpVerdict verdict);

/// The result of aligning one object to a model.
struct Alignment {
  IcpVerdict verdict = IcpVerdict::kTooFewPoints;
  IcpConvergence convergence = IcpConvergence::kNotConverged;
  /// m^2, mean squared distance of the aligned object's points to their nearest target
  /// points; not a number when ICP did not run.
  double fitness = 0.0;
  /// Maps the object onto the model (identity when ICP did not run).
  Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();
  double translation = 0.0;   ///< m, of `transform`
  double rotation_deg = 0.0;  ///< deg, angle of `transform`'s rotation
};

/// Aligns `object` to `target` with ICP and judges the result as IcpConfig describes;
/// `aligned`, when given, receives the object moved by the alignment's transform. The target
/// is used as given (IcpConfig::target_leaf_size is for concatenateWithIcp).
Alignment alignToModel(const ModelCloud& object, const ModelCloud& target,
                       const IcpConfig& config, ModelCloud* aligned = nullptr);

/// An ICP-aligned concatenation.
struct IcpConcatenation {
  /// The seed followed by every kept object, aligned.
  ModelCloud model;
  /// One per object, in the objects' order; the seed objects' entries say kept with an
  /// identity transform and convergence kNotConverged (they were not aligned).
  std::vector<Alignment> alignments;
  std::size_t kept = 0;  ///< objects kept, seed objects included
};

/// ICP concatenation (report 5.2.2): the model starts as `seed`; every object not listed in
/// `seed_objects` is aligned, in decreasing order of points (ties: lower index first), to the
/// model grown so far (through a voxel grid of config.target_leaf_size), and added to it when
/// kept. `seed_objects` are indices of objects already in the seed; they are counted as kept.
/// `progress`, when set, is called after each alignment with (objects aligned so far, objects
/// to align, i.e. those not in the seed).
IcpConcatenation concatenateWithIcp(
    const std::vector<ModelCloud>& objects, const ModelCloud& seed,
    const std::vector<std::size_t>& seed_objects, const IcpConfig& config,
    const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace granular
