#pragma once

#include <chrono>
#include <optional>

namespace granular_ros {

/// At most one warning per period on the wall clock. ROS's *_THROTTLE macros read ros::Time,
/// which plays a bag's clock: 0 until the first /clock message, when the first cloud may
/// already have come, and the first frame's warning was then kept back.
class WallThrottle {
 public:
  explicit WallThrottle(std::chrono::steady_clock::duration period = std::chrono::seconds(10))
      : period_(period) {}

  /// Whether a warning may go out now; if so, the next one waits a period from now.
  bool due() {
    const auto now = std::chrono::steady_clock::now();
    if (last_ && now - *last_ < period_) {
      return false;
    }
    last_ = now;
    return true;
  }

 private:
  std::chrono::steady_clock::duration period_;
  std::optional<std::chrono::steady_clock::time_point> last_;
};

}  // namespace granular_ros
