#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "granular_core/geometry/oriented_box.h"
#include "granular_core/tracking/tracking_config.h"

namespace granular {

/// One cuboid of a frame, as the tracker takes it.
struct Observation {
  OrientedBox box;
  std::string label;
  double score = 1.0;
  /// The object's points the fit used (0: not counted; weighs as 1 in a vote by points).
  std::size_t points = 0;
};

/// A tentative track's observation in a frame before its birth.
struct EarlierObservation {
  std::size_t frames_before = 0;  ///< 1: the frame before the one it is born in
  std::size_t observation = 0;    ///< an index into that frame's input
  bool operator==(const EarlierObservation& other) const {
    return frames_before == other.frames_before && observation == other.observation;
  }
};

/// A reported track, as of the latest frame.
struct Track {
  std::uint32_t id = 0;  ///< from 1, in the order tracks were born; never reused
  /// The filtered box: x-y centre from the filter, yaw the median of the latest detections'
  /// (along the velocity above heading_min_speed), size and centre height smoothed; turned
  /// about the sensor's z only.
  OrientedBox box;
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< m/s, x-y in the sensor frame
  /// The class its frames decided so far (TrackingConfig::vote; the abstain label until a
  /// frame votes) and the share of the weight of the votes that went to it (0 before any).
  std::string label;
  double share = 0.0;
  std::size_t hits = 0;    ///< frames with a detection, in all
  std::size_t misses = 0;  ///< frames in a row without one, up to the latest
  /// In a frame with an observation: the frames in a row without one just before (it coasted
  /// through them; an offline user may bridge them). 0 otherwise.
  std::size_t gap = 0;
  /// This frame's observation (an index into update's input); none while the track coasts.
  std::optional<std::size_t> observation;
  /// In the frame the track is born only: its observations in the frames before, while it was
  /// tentative (birth_hits - 1 of them, within the birth_hits - 1 + birth_misses frames
  /// before), and with backfill_gap those of the ended tentative tracks it continued (see
  /// TrackingConfig::backfill_gap), oldest first. An offline user may report the track there
  /// too; empty otherwise.
  std::vector<EarlierObservation> earlier_observations;
};

/// The turn about the sensor's z (the box's own front kept) that brings `observed` (the box of
/// a track's observation) to the track's smoothed yaw, or none where that turn is more than
/// `max_turn_deg` (TrackingConfig::max_turn_deg). fit_cuboids writes and segment_cloud
/// publishes a tracked cuboid so turned, its centre and size the observation's: the smoothed
/// yaw misses the paper's 10 degrees less often than the frame's own (docs/tracking.md), and
/// the fitted centre less often than the filter's, which lags the cuboid's jumps.
Eigen::Quaterniond turnToTrack(const Track& track, const OrientedBox& observed,
                               double max_turn_deg);

/// Multi-object tracking of cuboids on the ground plane, frame by frame (docs/tracking.md): a
/// constant-velocity Kalman filter per track (x, y, vx, vy), the least-cost assignment of
/// detections to tracks on the x-y distance between the detection's centre and the track's
/// predicted one, gated on that distance and on the footprints' overlap; a track is born after
/// `birth_hits` frames with a detection (missing at most `birth_misses` in between) and dies
/// after `death_misses` frames in a row without one; its class is decided over its frames. The sensor's own motion is not taken
/// out: positions are in the sensor frame of each frame.
class Tracker {
 public:
  /// Throws std::invalid_argument for a config out of range.
  explicit Tracker(const TrackingConfig& config = TrackingConfig());

  /// Takes one frame's observations at `stamp` (s) and returns the reported tracks: those born,
  /// not yet dead, ordered by id, each with this frame's observation or none. Throws
  /// std::invalid_argument when `stamp` is not finite or not after the previous frame's.
  std::vector<Track> update(double stamp, const std::vector<Observation>& observations);

  /// Tracks born so far (the reported ids run from 1 to this).
  std::uint32_t born() const { return next_id_ - 1; }

  /// How many frames before the latest one the oldest observation of a live tentative track
  /// is (0 without one): a track born in the next frame may name observations up to this plus
  /// one frames before it (Track::earlier_observations), which an offline user must still hold.
  std::size_t tentativeReach() const;

 private:
  struct State {
    std::uint32_t id = 0;  // 0 while tentative
    Eigen::Vector4d x = Eigen::Vector4d::Zero();  // x, y, vx, vy
    Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
    double yaw = 0.0;  // modulo pi until the track moves
    std::deque<double> yaws;  // the latest detections' yaws, yaw_window at most
    double z = 0.0;
    Eigen::Vector3d size = Eigen::Vector3d::Ones();
    std::size_t hits = 0;
    std::size_t misses = 0;  // in a row
    std::size_t gap = 0;  // the misses in a row before this frame's observation
    std::size_t tentative_misses = 0;  // in all, while tentative
    // A tentative track that missed more than birth_misses times: it takes no detection, and
    // is kept (backfill_gap) for a new track started near it to take its frames.
    bool ended = false;
    std::optional<std::size_t> observation;
    // Until born: (frame number, observation index) of each hit.
    std::vector<std::pair<std::size_t, std::size_t>> tentative_observations;
    // Per label, the votes or scores so far and the frame of its latest vote (ties).
    std::map<std::string, double> weights;
    std::map<std::string, std::size_t> last_vote;
  };
  // The track's predicted box at the stamp being taken (the filter's x-y, the rest smoothed).
  OrientedBox predictedBox(const State& state) const;
  Track reported(const State& state) const;
  // Pairs the tracks `tracks` (indices into states_) with the observations not yet `taken`,
  // each within its gates, at the least total cost; marks what it pairs in `assigned` (per
  // state) and `taken`.
  void associate(const std::vector<std::size_t>& tracks,
                 const std::vector<Observation>& observations, std::vector<bool>& taken,
                 std::vector<std::optional<std::size_t>>& assigned) const;
  // Takes a detection's yaw into the track's: the median of the latest yaw_window.
  void takeYaw(State& state, double yaw) const;
  // Adds the observation's label to the track's class decision (the abstain label does not
  // vote).
  void vote(State& state, const Observation& observation) const;

  TrackingConfig config_;
  std::vector<State> states_;  // live tracks, tentative and reported, oldest first
  std::optional<double> last_stamp_;
  std::uint32_t next_id_ = 1;
  std::size_t frames_ = 0;  // frames taken, for the ties of the class decision
};

}  // namespace granular
