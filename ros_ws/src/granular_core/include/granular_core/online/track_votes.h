#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace granular {

/// A track's decision.
struct TrackLabel {
  std::string label;      ///< the label with the most weight of the track's votes
  double share = 0.0;     ///< of the weight of its votes that went to that label, in (0, 1]
  std::size_t votes = 0;  ///< frames the track has voted in
};

/// One vote per frame for each track (a detection id, stable across frames as in the second
/// paper's tracking): a track's label is the one its frames gave the most weight so far; on a tie
/// it keeps the label it held (docs/online.md has what it gives). Tracks not seen for
/// `forget_after` seconds are dropped: ids are reused.
class TrackVotes {
 public:
  explicit TrackVotes(double forget_after = 2.0) : forget_after_(forget_after) {}

  /// Counts `label` for track `id` at `stamp` (s) with `weight` (a frame's points, or 1 for
  /// one vote a frame) and returns the track's label.
  TrackLabel vote(std::int64_t id, const std::string& label, double stamp, double weight = 1.0);
  /// Drops the tracks last seen before stamp - forget_after.
  void forget(double stamp);
  std::size_t tracks() const { return tracks_.size(); }

 private:
  struct Track {
    std::map<std::string, double> weights;
    double total = 0.0;
    std::size_t votes = 0;
    double last_seen = 0.0;
    std::string held;  // the label decided in its latest frame
  };
  double forget_after_;
  std::map<std::int64_t, Track> tracks_;
};

}  // namespace granular
