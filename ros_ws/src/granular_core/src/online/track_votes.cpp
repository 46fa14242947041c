#include "granular_core/online/track_votes.h"

namespace granular {

TrackLabel TrackVotes::vote(std::int64_t id, const std::string& label, double stamp) {
  Track& track = tracks_[id];
  ++track.counts[label];
  ++track.votes;
  track.last_seen = stamp;
  TrackLabel decision{label, 0.0, track.votes};
  std::size_t most = track.counts[label];  // ties go to this frame's label
  for (const auto& [name, count] : track.counts) {
    if (count > most) {
      most = count;
      decision.label = name;
    }
  }
  decision.share = static_cast<double>(most) / static_cast<double>(track.votes);
  return decision;
}

void TrackVotes::forget(double stamp) {
  for (auto track = tracks_.begin(); track != tracks_.end();) {
    track = track->second.last_seen < stamp - forget_after_ ? tracks_.erase(track)
                                                            : std::next(track);
  }
}

}  // namespace granular
