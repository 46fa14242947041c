#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace granular {

/// Exact nearest-point queries near a fixed cloud through a uniform grid of cells: a query
/// looks at its own cell, then at the cells that the ball of the best distance so far (or of
/// the bound) overlaps, or, with no such ball, at the rings of cells around its own, nearest
/// first, and stops as soon as no point beyond can be nearer. Most queries of a registration
/// land on or near the model, where a few cells answer them; a query that the rings cannot
/// settle says so, and the caller asks a kd-tree.
///
/// Squared distances are computed in float as FLANN's L2_Simple does,
/// ((0 + dx*dx) + dy*dy) + dz*dz, so a distance found here is the one PCL's KdTreeFLANN gives
/// for the same point, to the bit.
class NearestGrid {
 public:
  struct Result {
    /// True when the answer is exact. False when a point beyond the searched rings might be
    /// nearer than `distance`: then `found`, `index` and `distance` are the best seen so far.
    bool resolved = false;
    bool found = false;      ///< a point lies within the bound
    std::size_t index = 0;   ///< of the nearest point, into the cloud given
    float distance = std::numeric_limits<float>::infinity();  ///< squared, m^2

    /// Takes point `candidate` at squared distance `squared` when it is nearer than the best
    /// so far, or as near with a lower index (FLANN's order among equals); true when taken.
    bool offer(std::size_t candidate, float squared) {
      if (squared < distance || (squared == distance && found && candidate < index)) {
        distance = squared;
        index = candidate;
        found = true;
        return true;
      }
      return false;
    }
  };

  /// Indexes `count` points given as x y z floats (all finite). `max_rings`: how many rings of
  /// cells around the query's own cell a query may search.
  NearestGrid(const float* xyz, std::size_t count, int max_rings = 3);

  /// The nearest point whose squared distance to `query` is below `bound` (squared, m^2).
  /// Thread-safe.
  Result nearest(const float query[3],
                 float bound = std::numeric_limits<float>::infinity()) const;

 private:
  // Offers the points of one cell to `result`.
  void scan(std::size_t cell, const float query[3], Result& result) const;

  float origin_[3] = {0.0f, 0.0f, 0.0f};
  float cell_ = 1.0f;
  int size_[3] = {0, 0, 0};
  int max_rings_;
  std::vector<std::uint32_t> cell_start_;  ///< points of cell c: [cell_start_[c], [c + 1])
  std::vector<std::uint8_t> near_;         ///< 1 for a cell within max_rings_ of a point
  std::vector<float> points_;              ///< x y z per point, cell by cell
  std::vector<std::uint32_t> indices_;     ///< index into the given cloud, per point
};

}  // namespace granular
