#include "granular_ros/latency.h"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <vector>

namespace granular_ros {

void LatencyStats::add(double milliseconds) {
  recent_.push_back(milliseconds);
  if (recent_.size() > window_) {
    recent_.pop_front();
  }
  ++frames_;
  sum_ += milliseconds;
  max_ = std::max(max_, milliseconds);
}

double LatencyStats::percentile95() const {
  if (recent_.empty()) {
    return 0.0;
  }
  std::vector<double> sorted(recent_.begin(), recent_.end());
  const std::size_t rank = (sorted.size() * 95 + 99) / 100 - 1;  // nearest rank
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(rank),
                   sorted.end());
  return sorted[rank];
}

std::string LatencyStats::recent() const {
  const double mean =
      recent_.empty() ? 0.0
                      : std::accumulate(recent_.begin(), recent_.end(), 0.0) / recent_.size();
  char text[160];
  std::snprintf(text, sizeof(text), "%zu frames, mean %.2f ms, p95 %.2f ms, max %.2f ms",
                recent_.size(), mean, percentile95(),
                recent_.empty() ? 0.0 : *std::max_element(recent_.begin(), recent_.end()));
  return text;
}

std::string LatencyStats::total() const {
  char text[160];
  std::snprintf(text, sizeof(text), "%zu frames, mean %.2f ms, p95 %.2f ms (last %zu), max %.2f ms",
                frames_, frames_ > 0 ? sum_ / frames_ : 0.0, percentile95(), recent_.size(),
                max_);
  return text;
}

}  // namespace granular_ros
