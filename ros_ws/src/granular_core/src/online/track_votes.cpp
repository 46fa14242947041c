#include "granular_core/online/track_votes.h"

namespace granular {

TrackLabel TrackVotes::vote(std::int64_t id, const std::string& label, double stamp,
                            double weight) {
  Track& track = tracks_[id];
  track.weights[label] += weight;
  track.total += weight;
  ++track.votes;
  track.last_seen = stamp;
  // A tie keeps the label the track holds: a tag that turned on every tie flickered in rviz
  // (docs/online.md#the-track-vote).
  if (track.held.empty()) {
    track.held = label;
  }
  double most = track.weights[track.held];
  for (const auto& [name, weight_so_far] : track.weights) {
    if (weight_so_far > most) {
      most = weight_so_far;
      track.held = name;
    }
  }
  return TrackLabel{track.held, most / track.total, track.votes};
}

void TrackVotes::forget(double stamp) {
  for (auto track = tracks_.begin(); track != tracks_.end();) {
    track = track->second.last_seen < stamp - forget_after_ ? tracks_.erase(track)
                                                            : std::next(track);
  }
}

}  // namespace granular
