#include "granular_core/classification/nearest_points.h"

#include <algorithm>
#include <numeric>

namespace granular {
namespace {

constexpr std::uint32_t kLeafPoints = 8;
constexpr int kMaxDepth = 64;

// Squared distance from `query` to a box, summed in the same axis order as flannSquaredDistance
// and from per-axis terms no larger than any contained point's: rounding is monotonic, so it
// never exceeds flannSquaredDistance(query, p) for a point p in the box, and pruning by it is exact.
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

}  // namespace

NearestPoints::NearestPoints(const float* xyz, std::size_t count)
    : points_(xyz, xyz + 3 * count), indices_(count) {
  std::iota(indices_.begin(), indices_.end(), 0u);
  if (count > 0) {
    nodes_.reserve(2 * (count / kLeafPoints + 1));
    nodes_.emplace_back();
    build(0, 0, static_cast<std::uint32_t>(count), 0);
  }
}

void NearestPoints::build(std::size_t node_index, std::uint32_t begin, std::uint32_t end,
                          int depth) {
  Node node;
  node.begin = begin;
  node.end = end;
  node.first_child = -1;
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
  std::pair<std::int32_t, float> stack[2 * kMaxDepth + 2];
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

}  // namespace granular
