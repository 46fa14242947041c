#include "granular_core/online/track_votes.h"

namespace granular {

TrackLabel TrackVotes::vote(std::int64_t id, const std::string& label, double stamp) {
  Track& track = tracks_[id];
  ++track.counts[label];
  ++track.votes;
  track.last_seen = stamp;
  // A tie keeps the label the track holds: a tag that turned on every tie flickered in rviz
  // (docs/online.md#the-track-vote).
  if (track.held.empty()) {
    track.held = label;
  }
  std::size_t most = track.counts[track.held];
  for (const auto& [name, count] : track.counts) {
    if (count > most) {
      most = count;
      track.held = name;
    }
  }
  return TrackLabel{track.held, static_cast<double>(most) / static_cast<double>(track.votes),
                    track.votes};
}

void TrackVotes::forget(double stamp) {
  for (auto track = tracks_.begin(); track != tracks_.end();) {
    track = track->second.last_seen < stamp - forget_after_ ? tracks_.erase(track)
                                                            : std::next(track);
  }
}

}  // namespace granular
