#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace granular {

/// The squared distance of two x y z points as FLANN's L2_Simple computes it, operation for
/// operation: ((0 + dx*dx) + dy*dy) + dz*dz in float.
inline float flannSquaredDistance(const float* a, const float* b) {
  float result = 0.0f;
  const float dx = a[0] - b[0];
  result += dx * dx;
  const float dy = a[1] - b[1];
  result += dy * dy;
  const float dz = a[2] - b[2];
  result += dz * dz;
  return result;
}

/// The squared distance from `query` to a box (its `low` and `high` corners, x y z), summed in
/// flannSquaredDistance's axis order from per-axis terms no larger than any contained point's:
/// rounding is monotonic, so it never exceeds flannSquaredDistance(query, p) for a point p in
/// the box, and pruning (or bounding) by it is exact.
template <typename Box>
inline float boxDistance(const float* query, const Box& box) {
  float result = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    float step = 0.0f;
    if (query[axis] < box.low[axis]) {
      step = box.low[axis] - query[axis];
    } else if (query[axis] > box.high[axis]) {
      step = query[axis] - box.high[axis];
    }
    result += step * step;
  }
  return result;
}

/// Exact nearest-point search in a fixed cloud: a kd-tree with a bounding box on every node,
/// searched nearest box first without allocation. With a good bound (the caller's guess of the
/// distance) a query far from the cloud visits only the few nodes whose boxes come that close,
/// where a tree that prunes by splitting planes alone visits many.
///
/// Squared distances are computed in float as FLANN's L2_Simple does,
/// ((0 + dx*dx) + dy*dy) + dz*dz, so a distance found here is the one PCL's KdTreeFLANN gives
/// for the same point, to the bit. Which of several points at exactly the same distance is
/// returned is not specified.
class NearestPoints {
 public:
  struct Result {
    bool found = false;     ///< a point lies within the bound
    std::size_t index = 0;  ///< of the nearest point, into the cloud given
    float distance = std::numeric_limits<float>::infinity();  ///< squared, m^2
  };

  /// Indexes `count` points given as x y z floats (all finite).
  NearestPoints(const float* xyz, std::size_t count);

  /// The nearest point whose squared distance to `query` is below `bound` (squared, m^2).
  /// Thread-safe.
  Result nearest(const float query[3],
                 float bound = std::numeric_limits<float>::infinity()) const;

  /// The squared distances of kPacket queries (x y z each) to their nearest points, each
  /// capped by its bound: min(bound, nearest distance), so exact for a bound at or above the
  /// nearest distance. One walk of the tree serves all the queries, and a leaf's points are
  /// measured four at a time. Queries close to one another, as consecutive points of a scan
  /// are, share most of their walk.
  static constexpr int kPacket = 4;
  void nearestDistances(const float queries[kPacket][3], const float bounds[kPacket],
                        float distances[kPacket]) const;

 private:
  struct Node {
    float low[3];
    float high[3];
    std::uint32_t begin;        ///< points of a leaf: [begin, end)
    std::uint32_t end;
    std::int32_t first_child;   ///< -1 for a leaf; the second child follows the first
    std::uint32_t packed;       ///< a leaf's points in xs_, ys_, zs_: [packed, packed + 4k)
  };

  // Fills nodes_[node] with the points [begin, end), splitting it while it is large.
  void build(std::size_t node, std::uint32_t begin, std::uint32_t end, int depth);

  std::vector<float> points_;          ///< x y z per point, in tree order
  // The points again, axis by axis, each leaf padded to a multiple of four with far points.
  std::vector<float> xs_, ys_, zs_;
  std::vector<std::uint32_t> indices_; ///< index into the given cloud, per point
  std::vector<Node> nodes_;            ///< nodes_[0] is the root
  int depth_ = 0;                      ///< of the deepest leaf
};

}  // namespace granular
