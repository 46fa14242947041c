#include "granular_core/tracking/tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "granular_core/geometry/overlap.h"
#include "granular_core/tracking/assignment.h"

namespace granular {
namespace {

// An angle's difference to 0 modulo pi, in [-pi/2, pi/2): a cuboid's front is not known.
double axisDifference(double angle) {
  return angle - M_PI * std::floor(angle / M_PI + 0.5);
}

OrientedBox boxOnGround(const Eigen::Vector2d& centre, double z, double yaw,
                        const Eigen::Vector3d& size) {
  return OrientedBox(Eigen::Vector3d(centre.x(), centre.y(), z),
                     Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())), size);
}

}  // namespace

Eigen::Quaterniond turnToTrack(const Track& track, const OrientedBox& observed,
                               double max_turn_deg) {
  const double turn = std::remainder(track.box.yaw() - observed.yaw(), M_PI);
  if (std::abs(turn) > max_turn_deg * M_PI / 180.0) {
    return Eigen::Quaterniond::Identity();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()));
}

Tracker::Tracker(const TrackingConfig& config) : config_(config) { validate(config_); }

OrientedBox Tracker::predictedBox(const State& state) const {
  return boxOnGround(state.x.head<2>(), state.z, state.yaw, state.size);
}

Track Tracker::reported(const State& state) const {
  Track track{state.id, predictedBox(state), Eigen::Vector2d::Zero(), config_.abstain_label,
              0.0, state.hits, state.misses, state.gap, state.observation, {}};
  track.velocity = state.x.tail<2>();
  const double speed = track.velocity.norm();
  if (speed >= config_.heading_min_speed) {
    // The front taken to be the end the velocity points to; the axis stays.
    const double heading = std::atan2(track.velocity.y(), track.velocity.x());
    const double yaw = heading + axisDifference(state.yaw - heading);
    track.box = boxOnGround(state.x.head<2>(), state.z, yaw, state.size);
  }
  double total = 0.0, best = 0.0;
  std::size_t best_frame = 0;
  for (const auto& [label, weight] : state.weights) {
    total += weight;
    const std::size_t frame = state.last_vote.at(label);
    if (weight > best || (weight == best && frame > best_frame)) {
      best = weight;
      best_frame = frame;
      track.label = label;
    }
  }
  track.share = total > 0.0 ? best / total : 0.0;
  return track;
}

std::vector<Track> Tracker::update(double stamp, const std::vector<Observation>& observations) {
  if (!std::isfinite(stamp) || (last_stamp_ && stamp <= *last_stamp_)) {
    throw std::invalid_argument("Tracker: frame stamp " + std::to_string(stamp) +
                                " is not after the previous frame's" +
                                (last_stamp_ ? " (" + std::to_string(*last_stamp_) + ")" : ""));
  }
  const double dt = last_stamp_ ? stamp - *last_stamp_ : 0.0;
  last_stamp_ = stamp;
  ++frames_;

  // Predict: constant velocity, the acceleration left out as white noise per axis.
  Eigen::Matrix4d transition = Eigen::Matrix4d::Identity();
  transition(0, 2) = transition(1, 3) = dt;
  const double q = config_.filter.acceleration_std * config_.filter.acceleration_std;
  Eigen::Matrix4d noise = Eigen::Matrix4d::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    noise(axis, axis) = q * std::pow(dt, 4) / 4.0;
    noise(axis, axis + 2) = noise(axis + 2, axis) = q * std::pow(dt, 3) / 2.0;
    noise(axis + 2, axis + 2) = q * dt * dt;
  }
  for (State& state : states_) {
    state.x = transition * state.x;
    state.covariance = transition * state.covariance * transition.transpose() + noise;
    state.observation.reset();
  }

  // Associate: born tracks first, then tentative ones with the cuboids left (a track a few
  // frames old took a parked car's cuboid from its born track in the frame after a misfit
  // had pulled the born one aside; parking lot, docs/tracking.md).
  std::vector<std::optional<std::size_t>> assigned(states_.size());
  std::vector<bool> taken(observations.size(), false);
  for (const bool born : {true, false}) {
    std::vector<std::size_t> tracks;
    for (std::size_t t = 0; t < states_.size(); ++t) {
      if ((states_[t].id != 0) == born && !states_[t].ended) {
        tracks.push_back(t);
      }
    }
    associate(tracks, observations, taken, assigned);
  }

  // Correct the matched tracks; count the misses of the others.
  const double r = config_.filter.position_std * config_.filter.position_std;
  for (std::size_t t = 0; t < states_.size(); ++t) {
    State& state = states_[t];
    if (!assigned[t]) {
      ++state.misses;
      state.gap = 0;
      state.tentative_misses += state.id == 0 ? 1 : 0;
      continue;
    }
    const std::size_t o = *assigned[t];
    const Observation& observation = observations[o];
    const Eigen::Vector2d innovation = observation.box.centre().head<2>() - state.x.head<2>();
    const Eigen::Matrix2d innovation_covariance =
        state.covariance.topLeftCorner<2, 2>() + r * Eigen::Matrix2d::Identity();
    const Eigen::Matrix<double, 4, 2> gain =
        state.covariance.leftCols<2>() * innovation_covariance.inverse();
    state.x += gain * innovation;
    const Eigen::Matrix<double, 2, 4> observed = Eigen::Matrix<double, 2, 4>::Identity();
    state.covariance = (Eigen::Matrix4d::Identity() - gain * observed) * state.covariance;
    takeYaw(state, observation.box.yaw());
    state.size += config_.filter.size_gain * (observation.box.size() - state.size);
    state.z += config_.filter.size_gain * (observation.box.centre().z() - state.z);
    vote(state, observation);
    state.observation = o;
    if (state.id == 0) {
      state.tentative_observations.emplace_back(frames_, o);
    }
    ++state.hits;
    state.gap = state.id != 0 ? state.misses : 0;
    state.misses = 0;
  }

  // A tentative track that missed more than birth_misses times in all ends: it takes no more
  // detections, and is kept through backfill_gap frames in a row without one for a track
  // started near its predicted place in a later frame to take its frames (in the frame it ends
  // in, no cuboid within its gates was left to start one).
  std::vector<std::size_t> ended;
  for (std::size_t t = 0; t < states_.size(); ++t) {
    State& state = states_[t];
    if (state.ended) {
      ended.push_back(t);
    }
    state.ended = state.ended || (state.id == 0 && state.tentative_misses > config_.birth_misses);
  }
  // Each observation no track took starts a tentative track; one within an ended track's gates
  // (the least total cost, as above) takes that track's frames before its own, for an offline
  // user to write back once it is born. Its filter, votes and birth are its own.
  std::vector<bool> taken_or_continuing = taken;  // `taken` still says which start tracks
  std::vector<std::optional<std::size_t>> continued(states_.size());
  associate(ended, observations, taken_or_continuing, continued);
  std::vector<std::optional<std::size_t>> earlier_track(observations.size());
  for (const std::size_t t : ended) {
    if (continued[t]) {
      earlier_track[*continued[t]] = t;
    }
  }

  const double v0 = config_.filter.initial_velocity_std * config_.filter.initial_velocity_std;
  std::vector<State> started;
  for (std::size_t o = 0; o < observations.size(); ++o) {
    if (taken[o]) {
      continue;
    }
    const OrientedBox& box = observations[o].box;
    State state;
    state.x << box.centre().x(), box.centre().y(), 0.0, 0.0;
    state.covariance.diagonal() << r, r, v0, v0;
    state.yaw = box.yaw();
    state.yaws = {box.yaw()};
    state.z = box.centre().z();
    state.size = box.size();
    vote(state, observations[o]);
    state.observation = o;
    if (earlier_track[o]) {
      State& earlier = states_[*earlier_track[o]];
      state.tentative_observations = std::move(earlier.tentative_observations);
      earlier.misses = config_.backfill_gap + 1;  // its frames are the new track's now
    }
    state.tentative_observations.emplace_back(frames_, o);
    state.hits = 1;
    started.push_back(std::move(state));
  }

  // Death: an ended tentative track missed more than backfill_gap times in a row (or its frames
  // went to a new track), a reported one death_misses times in a row.
  std::vector<State> alive;
  for (State& state : states_) {
    const bool dead = state.id == 0 ? state.ended && state.misses > config_.backfill_gap
                                    : state.misses >= config_.death_misses;
    if (!dead) {
      alive.push_back(std::move(state));
    }
  }
  states_ = std::move(alive);
  for (State& state : started) {
    states_.push_back(std::move(state));
  }

  // Birth, in the order the tracks were started.
  std::vector<Track> tracks;
  for (State& state : states_) {
    const bool born = state.id == 0 && state.observation && state.hits >= config_.birth_hits;
    if (born) {
      state.id = next_id_++;
    }
    if (state.id != 0) {
      tracks.push_back(reported(state));
    }
    if (born) {
      state.tentative_observations.pop_back();  // this frame's: `observation`
      for (const auto& [frame, observation] : state.tentative_observations) {
        tracks.back().earlier_observations.push_back({frames_ - frame, observation});
      }
      state.tentative_observations.clear();
    }
  }
  std::sort(tracks.begin(), tracks.end(),
            [](const Track& a, const Track& b) { return a.id < b.id; });
  return tracks;
}

std::size_t Tracker::tentativeReach() const {
  std::size_t reach = 0;
  for (const State& state : states_) {
    if (state.id == 0) {
      reach = std::max(reach, frames_ - state.tentative_observations.front().first);
    }
  }
  return reach;
}

void Tracker::associate(const std::vector<std::size_t>& tracks,
                        const std::vector<Observation>& observations, std::vector<bool>& taken,
                        std::vector<std::optional<std::size_t>>& assigned) const {
  // The least total cost, where a pair costs its centre distance and a track left without a
  // cuboid costs its gate radius (a cuboid left out, nothing). Asking for the most pairs first
  // instead shifted a parked row's tracks by one car each wherever a car at its end was
  // missed and one at the other end seen (parking lot, docs/tracking.md): a track seen once
  // has a gate wider than the row's spacing. So each track has a column of its own that
  // stands for "none", after the cuboids' columns.
  const std::size_t columns = observations.size() + tracks.size();
  std::vector<double> costs(tracks.size() * columns, std::numeric_limits<double>::infinity());
  const double r = config_.filter.position_std * config_.filter.position_std;
  for (std::size_t row = 0; row < tracks.size(); ++row) {
    const State& state = states_[tracks[row]];
    const OrientedBox predicted = predictedBox(state);
    const Eigen::Matrix2d innovation_covariance =
        state.covariance.topLeftCorner<2, 2>() + r * Eigen::Matrix2d::Identity();
    const double largest_std =
        std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(innovation_covariance,
                                                                  Eigen::EigenvaluesOnly)
                      .eigenvalues()
                      .maxCoeff());
    const double radius = std::max(config_.gate.max_distance, config_.gate.sigmas * largest_std);
    const bool seen_once = state.hits == 1;
    const bool overlap_gated = config_.gate.min_overlap > 0.0 && !seen_once;
    const Eigen::Vector2d across(-std::sin(state.yaw), std::cos(state.yaw));
    for (std::size_t o = 0; o < observations.size(); ++o) {
      const OrientedBox& box = observations[o].box;
      const Eigen::Vector2d offset = box.centre().head<2>() - state.x.head<2>();
      const double distance = offset.norm();
      if (!taken[o] && distance <= radius &&
          (!seen_once || std::abs(offset.dot(across)) <= config_.gate.max_sideways) &&
          (!overlap_gated || birdEyeOverlap(predicted, box) >= config_.gate.min_overlap)) {
        costs[row * columns + o] = distance;
      }
    }
    costs[row * columns + observations.size() + row] = radius;
  }
  const std::vector<std::optional<std::size_t>> columns_assigned =
      assignMinimumCost(costs, tracks.size(), columns);
  for (std::size_t row = 0; row < tracks.size(); ++row) {
    const std::optional<std::size_t>& column = columns_assigned[row];
    if (column && *column < observations.size()) {
      assigned[tracks[row]] = *column;
      taken[*column] = true;
    }
  }
}

void Tracker::takeYaw(State& state, double yaw) const {
  state.yaws.push_back(yaw);
  while (state.yaws.size() > config_.filter.yaw_window) {
    state.yaws.pop_front();
  }
  // Each yaw as its difference modulo pi to the latest, so that a flipped front counts as
  // the same axis; the median of those differences, of the two middle ones for an even count.
  std::vector<double> differences;
  for (const double earlier : state.yaws) {
    differences.push_back(axisDifference(earlier - yaw));
  }
  std::sort(differences.begin(), differences.end());
  const std::size_t n = differences.size();
  const double median =
      n % 2 == 1 ? differences[n / 2] : 0.5 * (differences[n / 2 - 1] + differences[n / 2]);
  state.yaw = yaw + median;
}

void Tracker::vote(State& state, const Observation& observation) const {
  if (observation.label == config_.abstain_label) {
    return;
  }
  double weight = 1.0;
  switch (config_.vote) {
    case ClassVote::kPoints:
      weight = observation.score *
               static_cast<double>(std::max<std::size_t>(observation.points, 1));
      break;
    case ClassVote::kScores:
      weight = observation.score;
      break;
    case ClassVote::kVotes:
      break;
  }
  state.weights[observation.label] += weight;
  state.last_vote[observation.label] = frames_;
}

}  // namespace granular
