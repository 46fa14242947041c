#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>

#include "granular_core/config/fields.h"

namespace granular {

/// How a track's frames decide its class.
enum class ClassVote {
  kScores,  ///< each frame adds its detection's score to its label
  kVotes,   ///< each frame adds one to its label
};

template <>
struct config::EnumNames<ClassVote> {
  static constexpr const char* what = "class vote";
  static constexpr std::array<std::pair<ClassVote, const char*>, 2> values{
      {{ClassVote::kScores, "scores"}, {ClassVote::kVotes, "votes"}}};
};

/// Which detection may continue which track: both gates must pass.
struct TrackingGateConfig {
  /// m: the detection's centre at most this far (x-y) from the track's predicted centre, ...
  double max_distance = 2.0;
  /// ... or, where more, this many standard deviations of the predicted centre (along its
  /// most uncertain direction, the detection's error included): a track seen once has no
  /// velocity yet, and a car coming the other way moves metres between frames.
  double sigmas = 3.0;
  /// The footprints' shared area over the smaller footprint's, at least this (0: the distance
  /// alone decides): two cars side by side in adjacent lanes do not overlap. Not asked of a
  /// track seen once, whose predicted place is not known well enough to overlap.
  double min_overlap = 0.1;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("max_distance", self.max_distance, positive("m"));
    visit("sigmas", self.sigmas, nonNegative("standard deviations"));
    visit("min_overlap", self.min_overlap, fraction());
  }
};

/// The constant-velocity Kalman filter on the ground plane (x, y, vx, vy), and the smoothing
/// of what it does not estimate.
struct TrackingFilterConfig {
  /// m: a detection's centre error (a cuboid grown from the corner seen moves its centre when
  /// the view changes).
  double position_std = 0.3;
  /// m/s^2: the acceleration the constant-velocity model leaves out (braking, turning).
  double acceleration_std = 2.0;
  /// m/s: what is known of a new track's velocity (it starts at 0).
  double initial_velocity_std = 10.0;
  /// Of a detection's yaw (modulo 180 degrees: a cuboid's front is not known) and of its
  /// size and height, this share is taken into the track's each frame (1: the latest alone).
  double yaw_gain = 0.3;
  double size_gain = 0.2;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("position_std", self.position_std, positive("m"));
    visit("acceleration_std", self.acceleration_std, positive("m/s^2"));
    visit("initial_velocity_std", self.initial_velocity_std, positive("m/s"));
    visit("yaw_gain", self.yaw_gain, interval(0, 1, "", true));
    visit("size_gain", self.size_gain, interval(0, 1, "", true));
  }
};

/// The multi-object tracker (Tracker): cuboids per frame in, tracks out (docs/tracking.md).
struct TrackingConfig {
  TrackingGateConfig gate;
  TrackingFilterConfig filter;
  /// A new track is reported (and numbered) once it has had a detection in this many frames
  /// in a row; a tentative track missed once is dropped. 5 rather than 3: clutter that the
  /// segmentation finds in a few frames in a row makes fewer tracks (simulated train drive,
  /// docs/tracking.md).
  std::size_t birth_hits = 5;
  /// A reported track is dropped after this many frames in a row without a detection.
  std::size_t death_misses = 3;
  ClassVote vote = ClassVote::kScores;
  /// The label that does not vote (a detection the classifier could not name).
  std::string abstain_label = "unknown";
  /// m/s: from this speed on, a track's yaw points along its velocity (below, the front is
  /// not known and the yaw is the detections' modulo 180 degrees).
  double heading_min_speed = 2.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("gate", self.gate);
    visit("filter", self.filter);
    visit("birth_hits", self.birth_hits, atLeast(1, "frames"));
    visit("death_misses", self.death_misses, atLeast(1, "frames"));
    visit("vote", self.vote);
    visit("abstain_label", self.abstain_label, text("a label"));
    visit("heading_min_speed", self.heading_min_speed, positive("m/s"));
  }
};

/// Throws std::invalid_argument naming the first field out of range.
void validate(const TrackingConfig& config);

}  // namespace granular
