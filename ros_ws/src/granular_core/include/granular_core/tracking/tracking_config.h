#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>

#include "granular_core/config/fields.h"

namespace granular {

/// How a track's frames decide its class.
enum class ClassVote {
  kPoints,  ///< each frame adds its detection's score times its points to its label
  kScores,  ///< each frame adds its detection's score to its label
  kVotes,   ///< each frame adds one to its label
};

template <>
struct config::EnumNames<ClassVote> {
  static constexpr const char* what = "class vote";
  static constexpr std::array<std::pair<ClassVote, const char*>, 3> values{
      {{ClassVote::kPoints, "points"},
       {ClassVote::kScores, "scores"},
       {ClassVote::kVotes, "votes"}}};
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
  /// m: a track seen once takes a detection at most this far across its first cuboid's length
  /// axis (a car moves along its length), where its widened gate would reach the next car of a
  /// parked row: a tentative track stepping from car to car was born as a track running along
  /// the row at 24 m/s and took a parked car's cuboid from that car's track (parking lot,
  /// docs/tracking.md).
  double max_sideways = 1.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("max_distance", self.max_distance, positive("m"));
    visit("sigmas", self.sigmas, nonNegative("standard deviations"));
    visit("min_overlap", self.min_overlap, fraction());
    visit("max_sideways", self.max_sideways, positive("m"));
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
  /// frames: a track's yaw is the median, modulo 180 degrees (a cuboid's front is not known),
  /// of its latest this many detections' yaws (1: the latest alone). A median rather than a
  /// running average: a track whose first cuboid was fitted across the car (a corner seen from
  /// afar) takes the right yaw once most of its frames say it, where an average lagged for
  /// frames (simulated test drive, docs/tracking.md).
  std::size_t yaw_window = 5;
  /// Of a detection's size and height, this share is taken into the track's each frame (1:
  /// the latest alone).
  double size_gain = 0.2;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("position_std", self.position_std, positive("m"));
    visit("acceleration_std", self.acceleration_std, positive("m/s^2"));
    visit("initial_velocity_std", self.initial_velocity_std, positive("m/s"));
    visit("yaw_window", self.yaw_window, atLeast(1, "frames"));
    visit("size_gain", self.size_gain, interval(0, 1, "", true));
  }
};

/// The multi-object tracker (Tracker): cuboids per frame in, tracks out (docs/tracking.md).
struct TrackingConfig {
  TrackingGateConfig gate;
  TrackingFilterConfig filter;
  /// A new track is reported (and numbered) once it has had a detection in this many frames
  /// (missing at most birth_misses in between). 5 rather than 3: clutter that the
  /// segmentation finds in a few frames in a row makes fewer tracks (simulated train drive,
  /// docs/tracking.md).
  std::size_t birth_hits = 5;
  /// frames: a tentative track may go without a detection in this many frames in all before
  /// it is born (0: a detection in every frame, birth_hits in a row); one more and it is
  /// dropped. 1 bears a car whose segment is lost every third frame, and the clutter that
  /// comes and goes as well: on the simulated train drive MOTA 0.689 with 0, 0.681 with 1
  /// (docs/tracking.md).
  std::size_t birth_misses = 0;
  /// A reported track is dropped after this many frames in a row without a detection. 6
  /// rather than 3: a car whose segment comes and goes behind its neighbours keeps its track
  /// (and its id) where a new one would need birth_hits frames in a row (simulated train
  /// drive: MOTA 0.689 with 3, 0.695 with 5 and 6, 0.693 with 8 and 10; docs/tracking.md).
  std::size_t death_misses = 6;
  /// Points rather than scores: a vehicle first seen far away, its few returns named with
  /// confidence, kept that class after it came near and showed its own (held-out simulated
  /// drive, seed 42: class-aware F1 per frame 0.897 with scores, 0.912 with points).
  ClassVote vote = ClassVote::kPoints;
  /// The label that does not vote (a detection the classifier could not name).
  std::string abstain_label = "unknown";
  /// m/s: from this speed on, a track's yaw points along its velocity (below, the front is
  /// not known and the yaw is the detections' modulo 180 degrees).
  double heading_min_speed = 2.0;
  /// deg: a tracked cuboid is written turned to its track's yaw (turnToTrack) only where that
  /// turns it by at most this; one that disagrees more with its track is written as fitted. A
  /// track born on cuboids fitted across the car (a crowded parking lot) has a yaw the
  /// right cuboids then disagree with by up to 90 degrees; of the turns above 20 degrees on
  /// the simulated drives, 15 broke a cuboid that passed and 2 mended one (docs/tracking.md).
  double max_turn_deg = 20.0;
  /// frames: offline (fit_cuboids), a track's frames without a cuboid between two with one (it
  /// coasted through them), this many at most, are written with a cuboid bridging them: centre
  /// and size moved evenly from the cuboid before to the one after, turned as the one after
  /// (0: none). Online nothing can wait. 2 rather than 1 with today's cuboids (and
  /// backfill_gap 4): MOTA 0.912 -> 0.915 on the simulated test drive, 0.832 -> 0.834 on the
  /// held-out drive of seed 42, 0.737 -> 0.741 on the parking lot; 3 gave the test drive
  /// 6 false cuboids more (docs/tracking.md).
  std::size_t bridge_frames = 2;
  /// frames: offline (fit_cuboids), a tentative track that ends (it missed more than
  /// birth_misses frames) is kept through this many frames in a row without a detection, taking
  /// none; a track started in a later frame within its gates takes its frames before its own,
  /// and once born is written there too (Track::earlier_observations). Its filter, class and
  /// birth are its own: the births are as with 0, which drops an ended track at once (online,
  /// where nothing can be written back). A car whose segment is lost for a frame in its first
  /// birth_hits frames is written from its first frame: 4 (0.8 s at 5 frames a second) wrote 6
  /// more true cuboids on each of four simulated drives, false ones as before (docs/tracking.md).
  std::size_t backfill_gap = 4;
  /// Offline (fit_cuboids), every cuboid of a track carries the class and share of the vote
  /// over all its frames, as the track ended; false: of its frames up to the cuboid's, as
  /// online. A track's early frames, far or half hidden, vote least well: simulated drives,
  /// class-aware F1 per frame with the vote by points, 0.943 -> 0.954 on the test drive,
  /// 0.887 -> 0.920 and 0.879 -> 0.911 on fresh ones, 0.799 -> 0.825 on the parking lot, 0.912
  /// -> 0.903 on seed 42 (docs/tracking.md).
  bool final_class = true;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("gate", self.gate);
    visit("filter", self.filter);
    visit("birth_hits", self.birth_hits, atLeast(1, "frames"));
    visit("birth_misses", self.birth_misses, nonNegative("frames"));
    visit("death_misses", self.death_misses, atLeast(1, "frames"));
    visit("vote", self.vote);
    visit("abstain_label", self.abstain_label, text("a label"));
    visit("heading_min_speed", self.heading_min_speed, positive("m/s"));
    visit("max_turn_deg", self.max_turn_deg, interval(0, 90, "deg"));
    visit("bridge_frames", self.bridge_frames, nonNegative("frames"));
    visit("backfill_gap", self.backfill_gap, nonNegative("frames"));
    visit("final_class", self.final_class);
  }
};

/// Throws std::invalid_argument naming the first field out of range.
void validate(const TrackingConfig& config);

}  // namespace granular
