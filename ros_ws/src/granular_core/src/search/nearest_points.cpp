#include "granular_core/search/nearest_points.h"

#include <algorithm>
#include <numeric>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace granular {
namespace {

constexpr std::uint32_t kLeafPoints = 128;
// Pads the leaves in xs_, ys_, zs_: its squared distance to any query is beyond every bound.
constexpr float kFarAway = 1.0e18f;
constexpr int kMaxDepth = 64;

}  // namespace

NearestPoints::NearestPoints(const float* xyz, std::size_t count)
    : points_(xyz, xyz + 3 * count), indices_(count) {
  std::iota(indices_.begin(), indices_.end(), 0u);
  if (count > 0) {
    nodes_.reserve(2 * (count / kLeafPoints + 1));
    nodes_.emplace_back();
    build(0, 0, static_cast<std::uint32_t>(count), 0);
  }
  for (Node& node : nodes_) {
    if (node.first_child >= 0) {
      continue;
    }
    node.packed = static_cast<std::uint32_t>(xs_.size());
    for (std::uint32_t p = node.begin; p < node.end; ++p) {
      xs_.push_back(points_[3 * p]);
      ys_.push_back(points_[3 * p + 1]);
      zs_.push_back(points_[3 * p + 2]);
    }
    while (xs_.size() % 4 != 0) {
      xs_.push_back(kFarAway);
      ys_.push_back(kFarAway);
      zs_.push_back(kFarAway);
    }
  }
}

void NearestPoints::build(std::size_t node_index, std::uint32_t begin, std::uint32_t end,
                          int depth) {
  Node node;
  node.begin = begin;
  node.end = end;
  node.first_child = -1;
  node.packed = 0;
  for (int axis = 0; axis < 3; ++axis) {
    node.low[axis] = node.high[axis] = points_[3 * begin + axis];
  }
  for (std::uint32_t i = begin; i < end; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      node.low[axis] = std::min(node.low[axis], points_[3 * i + axis]);
      node.high[axis] = std::max(node.high[axis], points_[3 * i + axis]);
    }
  }
  depth_ = std::max(depth_, depth);
  if (end - begin <= kLeafPoints || depth >= kMaxDepth) {
    nodes_[node_index] = node;
    return;
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (node.high[a] - node.low[a] > node.high[axis] - node.low[axis]) {
      axis = a;
    }
  }
  // Split at the median along the widest axis.
  std::vector<std::uint32_t> order(end - begin);
  std::iota(order.begin(), order.end(), begin);
  const std::uint32_t middle = (end - begin) / 2;
  std::nth_element(order.begin(), order.begin() + middle, order.end(),
                   [&](std::uint32_t a, std::uint32_t b) {
                     return points_[3 * a + axis] < points_[3 * b + axis];
                   });
  std::vector<float> points(3 * order.size());
  std::vector<std::uint32_t> indices(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    std::copy(&points_[3 * order[k]], &points_[3 * order[k]] + 3, &points[3 * k]);
    indices[k] = indices_[order[k]];
  }
  std::copy(points.begin(), points.end(), points_.begin() + 3 * begin);
  std::copy(indices.begin(), indices.end(), indices_.begin() + begin);

  node.first_child = static_cast<std::int32_t>(nodes_.size());
  nodes_[node_index] = node;
  nodes_.emplace_back();
  nodes_.emplace_back();
  build(static_cast<std::size_t>(node.first_child), begin, begin + middle, depth + 1);
  build(static_cast<std::size_t>(node.first_child) + 1, begin + middle, end, depth + 1);
}

NearestPoints::Result NearestPoints::nearest(const float query[3], float bound) const {
  Result result;
  result.distance = bound;
  if (nodes_.empty()) {
    return result;
  }
  // A stack of nodes to visit with their box distances; the nearer child is visited first.
  // (Left uninitialised: it is written before it is read, and zeroing it costs a search.)
  struct Pending {
    std::int32_t index;
    float reach;
  };
  Pending stack[2 * kMaxDepth + 2];
  int top = 0;
  stack[top++] = {0, boxDistance(query, nodes_[0])};
  while (top > 0) {
    const auto [index, reach] = stack[--top];
    if (reach >= result.distance) {
      continue;
    }
    const Node& node = nodes_[static_cast<std::size_t>(index)];
    if (node.first_child < 0) {
      for (std::uint32_t p = node.begin; p < node.end; ++p) {
        const float distance = flannSquaredDistance(query, &points_[3 * p]);
        if (distance < result.distance) {
          result.distance = distance;
          result.index = indices_[p];
          result.found = true;
        }
      }
      continue;
    }
    const std::int32_t first = node.first_child;
    const float first_reach = boxDistance(query, nodes_[static_cast<std::size_t>(first)]);
    const float second_reach = boxDistance(query, nodes_[static_cast<std::size_t>(first) + 1]);
    // Pushed far first, so the near child is popped next.
    if (first_reach <= second_reach) {
      stack[top++] = {first + 1, second_reach};
      stack[top++] = {first, first_reach};
    } else {
      stack[top++] = {first, first_reach};
      stack[top++] = {first + 1, second_reach};
    }
  }
  return result;
}

#ifdef __SSE2__

namespace {

// boxDistance() of four queries (one per lane) at once, with the same operations per lane.
inline __m128 boxDistances(const __m128 query[3], const float low[3], const float high[3]) {
  __m128 result = _mm_setzero_ps();
  for (int axis = 0; axis < 3; ++axis) {
    // Below the box: low - q > 0; above: q - high > 0; inside: both <= 0, so 0.
    const __m128 below = _mm_sub_ps(_mm_set1_ps(low[axis]), query[axis]);
    const __m128 above = _mm_sub_ps(query[axis], _mm_set1_ps(high[axis]));
    const __m128 step = _mm_max_ps(_mm_max_ps(below, above), _mm_setzero_ps());
    result = _mm_add_ps(result, _mm_mul_ps(step, step));
  }
  return result;
}

inline float laneSum(__m128 values) {
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, values);
  return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
}

}  // namespace

void NearestPoints::nearestDistances(const float queries[kPacket][3],
                                     const float bounds[kPacket],
                                     float distances[kPacket]) const {
  static_assert(kPacket == 4, "one SSE register of queries");
  std::copy(bounds, bounds + kPacket, distances);
  if (nodes_.empty()) {
    return;
  }
  __m128 query[3];
  for (int axis = 0; axis < 3; ++axis) {
    query[axis] = _mm_setr_ps(queries[0][axis], queries[1][axis], queries[2][axis],
                              queries[3][axis]);
  }
  __m128 best = _mm_loadu_ps(distances);

  struct Pending {
    __m128 reach;
    std::int32_t index;
  };
  Pending stack[2 * kMaxDepth + 2];
  int top = 0;
  stack[top++] = {boxDistances(query, nodes_[0].low, nodes_[0].high), 0};
  while (top > 0) {
    const Pending pending = stack[--top];
    // A node is visited for the queries whose best it may still better.
    const int lanes = _mm_movemask_ps(_mm_cmplt_ps(pending.reach, best));
    if (lanes == 0) {
      continue;
    }
    const Node& node = nodes_[static_cast<std::size_t>(pending.index)];
    if (node.first_child < 0) {
      const std::uint32_t end = node.packed + ((node.end - node.begin + 3) / 4) * 4;
      for (int lane = 0; lane < kPacket; ++lane) {
        if ((lanes & (1 << lane)) == 0) {
          continue;
        }
        const __m128 x = _mm_set1_ps(queries[lane][0]);
        const __m128 y = _mm_set1_ps(queries[lane][1]);
        const __m128 z = _mm_set1_ps(queries[lane][2]);
        __m128 nearest = _mm_set1_ps(distances[lane]);
        for (std::uint32_t p = node.packed; p < end; p += 4) {
          // flannSquaredDistance() for four points: ((0 + dx*dx) + dy*dy) + dz*dz, where
          // 0 + dx*dx is dx*dx exactly.
          const __m128 dx = _mm_sub_ps(x, _mm_loadu_ps(&xs_[p]));
          const __m128 dy = _mm_sub_ps(y, _mm_loadu_ps(&ys_[p]));
          const __m128 dz = _mm_sub_ps(z, _mm_loadu_ps(&zs_[p]));
          nearest = _mm_min_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)),
                                          _mm_mul_ps(dz, dz)),
                               nearest);
        }
        alignas(16) float four[4];
        _mm_store_ps(four, nearest);
        distances[lane] = std::min(std::min(four[0], four[1]), std::min(four[2], four[3]));
      }
      best = _mm_loadu_ps(distances);
      continue;
    }
    const std::int32_t first = node.first_child;
    const Node& first_node = nodes_[static_cast<std::size_t>(first)];
    const Node& second_node = nodes_[static_cast<std::size_t>(first) + 1];
    const __m128 first_reach = boxDistances(query, first_node.low, first_node.high);
    const __m128 second_reach = boxDistances(query, second_node.low, second_node.high);
    // The child nearer to the queries as a whole is popped next.
    if (laneSum(first_reach) <= laneSum(second_reach)) {
      stack[top++] = {second_reach, first + 1};
      stack[top++] = {first_reach, first};
    } else {
      stack[top++] = {first_reach, first};
      stack[top++] = {second_reach, first + 1};
    }
  }
}

#else

void NearestPoints::nearestDistances(const float queries[kPacket][3],
                                     const float bounds[kPacket],
                                     float distances[kPacket]) const {
  for (int lane = 0; lane < kPacket; ++lane) {
    distances[lane] = nearest(queries[lane], bounds[lane]).distance;
  }
}

#endif

}  // namespace granular
