#pragma once

#include <cstddef>
#include <deque>
#include <string>

namespace granular_ros {

/// Processing times of a node's frames: the last `window` for the mean and 95th percentile it
/// logs while running, and the whole run's for the summary at the end.
class LatencyStats {
 public:
  explicit LatencyStats(std::size_t window = 1000) : window_(window) {}

  void add(double milliseconds);
  std::size_t frames() const { return frames_; }
  /// "N frames, mean X ms, p95 Y ms, max Z ms" over the window.
  std::string recent() const;
  /// The same over the whole run (mean and max; p95 over the window).
  std::string total() const;

 private:
  double percentile95() const;

  std::size_t window_;
  std::deque<double> recent_;
  std::size_t frames_ = 0;
  double sum_ = 0.0;
  double max_ = 0.0;
};

}  // namespace granular_ros
