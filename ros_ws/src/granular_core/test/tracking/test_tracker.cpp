// The tracker on synthetic frames with known answers: ids kept through a crossing and a missed
// frame, births and deaths counted, the class decided over the frames, the velocity and the
// heading estimated, and the gates holding.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "granular_core/tracking/tracker.h"

namespace granular {
namespace {

constexpr double kPeriod = 0.1;  // s, the simulator's and KITTI's 10 Hz

Observation car(double x, double y, double yaw = 0.0, const std::string& label = "unknown",
                double score = 1.0) {
  return Observation{
      OrientedBox(Eigen::Vector3d(x, y, 0.8),
                  Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
                  Eigen::Vector3d(4.5, 1.8, 1.6)),
      label, score};
}

// Births after three hits, as the tests count frames (the default is 5: fewer tracks of
// clutter on the simulator's drives, docs/tracking.md).
TrackingConfig threeHits() {
  TrackingConfig config;
  config.birth_hits = 3;
  return config;
}

// The id of the reported track holding observation `index` this frame; 0 when none does.
std::uint32_t idOf(const std::vector<Track>& tracks, std::size_t index) {
  for (const Track& track : tracks) {
    if (track.observation == index) {
      return track.id;
    }
  }
  return 0;
}

TEST(TrackerTest, TwoObjectsCrossingPathsKeepTheirIds) {
  // A heads up and B down a shallow X at 10 m/s, meeting between two frames: at x = 0.5 each
  // is nearer the other's last place (1.0 m) than its own (1.04 m), so only the motion
  // keeps them apart. The observations come in a different order every frame.
  Tracker tracker(threeHits());
  const double slope = 0.3;
  std::map<std::string, std::uint32_t> ids;
  for (int k = 0; k < 20; ++k) {
    const double x = -9.5 + k;
    const Observation a = car(x, slope * x, std::atan(slope));
    const Observation b = car(x, -slope * x, -std::atan(slope));
    const bool a_first = k % 2 == 0;
    const std::vector<Track> tracks =
        tracker.update(k * kPeriod, a_first ? std::vector<Observation>{a, b}
                                            : std::vector<Observation>{b, a});
    if (k < 2) {  // tentative for the first birth_hits - 1 frames
      EXPECT_TRUE(tracks.empty()) << "frame " << k;
      continue;
    }
    ASSERT_EQ(tracks.size(), 2u) << "frame " << k;
    const std::uint32_t id_a = idOf(tracks, a_first ? 0 : 1);
    const std::uint32_t id_b = idOf(tracks, a_first ? 1 : 0);
    if (k == 2) {
      ids["a"] = id_a;
      ids["b"] = id_b;
      EXPECT_NE(id_a, id_b);
    }
    EXPECT_EQ(id_a, ids["a"]) << "frame " << k << ", x " << x;
    EXPECT_EQ(id_b, ids["b"]) << "frame " << k << ", x " << x;
  }
  EXPECT_EQ(tracker.born(), 2u);
}

TEST(TrackerTest, AnObjectMissedForOneFrameKeepsItsId) {
  Tracker tracker(threeHits());
  for (int k = 0; k < 12; ++k) {
    std::vector<Observation> frame;
    if (k != 6) {
      frame.push_back(car(5.0 + 1.2 * k, 3.0));  // 12 m/s along x
    }
    const std::vector<Track> tracks = tracker.update(k * kPeriod, frame);
    if (k < 2) {
      EXPECT_TRUE(tracks.empty());
      continue;
    }
    ASSERT_EQ(tracks.size(), 1u) << "frame " << k;
    EXPECT_EQ(tracks[0].id, 1u);
    if (k == 6) {  // coasting: reported without an observation, where it would be
      EXPECT_FALSE(tracks[0].observation);
      EXPECT_EQ(tracks[0].misses, 1u);
      EXPECT_NEAR(tracks[0].box.centre().x(), 5.0 + 1.2 * 6, 0.3);
    } else {
      EXPECT_EQ(tracks[0].observation, 0u);
      EXPECT_EQ(tracks[0].gap, k == 7 ? 1u : 0u) << "frame " << k;  // the frame it coasted
    }
  }
  EXPECT_EQ(tracker.born(), 1u);
}

TEST(TrackerTest, ATrackWhoseFramesSaySedanSedanSuvSedanIsASedan) {
  for (const ClassVote vote : {ClassVote::kPoints, ClassVote::kScores, ClassVote::kVotes}) {
    TrackingConfig config = threeHits();
    config.vote = vote;
    config.birth_hits = 1;
    Tracker tracker(config);
    const std::vector<std::string> labels = {"Sedan", "Sedan", "SUV", "Sedan"};
    std::vector<Track> tracks;
    for (std::size_t k = 0; k < labels.size(); ++k) {
      tracks = tracker.update(k * kPeriod, {car(10.0, 0.0, 0.0, labels[k], 0.8)});
      ASSERT_EQ(tracks.size(), 1u);
    }
    EXPECT_EQ(tracks[0].label, "Sedan") << config::enumName(vote);
    EXPECT_DOUBLE_EQ(tracks[0].share, 0.75) << config::enumName(vote);
  }
}

TEST(TrackerTest, TheClassVoteWeighsScoresOrCountsFramesAndUnknownAbstains) {
  const std::vector<Observation> frames = {car(10, 0, 0, "Sedan", 0.3), car(10, 0, 0, "unknown"),
                                           car(10, 0, 0, "Sedan", 0.3), car(10, 0, 0, "SUV", 0.9),
                                           car(10, 0, 0, "unknown")};
  const auto decide = [&](ClassVote vote) {
    TrackingConfig config = threeHits();
    config.vote = vote;
    config.birth_hits = 1;
    Tracker tracker(config);
    std::vector<Track> tracks;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      tracks = tracker.update(k * kPeriod, {frames[k]});
    }
    return tracks.at(0);
  };
  const Track by_scores = decide(ClassVote::kScores);
  EXPECT_EQ(by_scores.label, "SUV");  // 0.9 against 0.6
  EXPECT_DOUBLE_EQ(by_scores.share, 0.6);
  const Track by_votes = decide(ClassVote::kVotes);
  EXPECT_EQ(by_votes.label, "Sedan");  // 2 against 1; the unknowns do not count
  EXPECT_DOUBLE_EQ(by_votes.share, 2.0 / 3.0);

  TrackingConfig config = threeHits();
  config.birth_hits = 1;
  Tracker tracker(config);
  const Track unnamed = tracker.update(0.0, {car(10, 0)}).at(0);
  EXPECT_EQ(unnamed.label, "unknown");
  EXPECT_EQ(unnamed.share, 0.0);
  // A tie goes to the latest frame's label.
  EXPECT_EQ(tracker.update(0.1, {car(10, 0, 0, "Jeep")}).at(0).label, "Jeep");
  EXPECT_EQ(tracker.update(0.2, {car(10, 0, 0, "SUV")}).at(0).label, "SUV");
  EXPECT_EQ(tracker.update(0.3, {car(10, 0, 0, "Jeep")}).at(0).label, "Jeep");
}

TEST(TrackerTest, AVoteByPointsLetsNearFramesOutweighFarSparseOnes) {
  // A bus coming near: four far frames of 30 points named BoxTruck with confidence, then
  // three near ones of 200 points named SchoolBus less surely.
  std::vector<Observation> frames;
  for (std::size_t k = 0; k < 7; ++k) {
    const bool near = k >= 4;
    Observation frame = car(30.0 - 0.5 * static_cast<double>(k), 0.0, 0.0,
                            near ? "SchoolBus" : "BoxTruck", near ? 0.7 : 1.0);
    frame.points = near ? 200 : 30;
    frames.push_back(frame);
  }
  const auto decide = [&](ClassVote vote) {
    TrackingConfig config = threeHits();
    config.vote = vote;
    config.birth_hits = 1;
    Tracker tracker(config);
    std::vector<Track> tracks;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      tracks = tracker.update(static_cast<double>(k) * kPeriod, {frames[k]});
    }
    return tracks.at(0);
  };
  const Track by_points = decide(ClassVote::kPoints);
  EXPECT_EQ(by_points.label, "SchoolBus");  // 3 x 0.7 x 200 = 420 against 4 x 30 = 120
  EXPECT_DOUBLE_EQ(by_points.share, 420.0 / 540.0);
  EXPECT_EQ(decide(ClassVote::kScores).label, "BoxTruck");  // 4.0 against 2.1
}

TEST(TrackerTest, BirthsAfterThreeHitsAndDeathsAfterThreeMisses) {
  // Object A is seen in frames 0-9, B in frames 4-5 only (never born), C in 3-14, and frame 7
  // holds clutter far from everything; birth_hits 3, death_misses 3.
  TrackingConfig config = threeHits();
  config.death_misses = 3;
  Tracker tracker(config);
  std::vector<std::size_t> reported;
  for (int k = 0; k < 20; ++k) {
    std::vector<Observation> frame;
    if (k <= 9) frame.push_back(car(10.0 + k, 0.0));
    if (k == 4 || k == 5) frame.push_back(car(-20.0, 8.0));
    if (k >= 3 && k <= 14) frame.push_back(car(0.0, -15.0 + 0.5 * k, M_PI / 2));
    if (k == 7) frame.push_back(car(30.0, 30.0));
    reported.push_back(tracker.update(k * kPeriod, frame).size());
  }
  // A from frame 2 to frame 11 (its third miss drops it in 12), C from 5 to 16.
  const std::vector<std::size_t> expected = {0, 0, 1, 1, 1, 2, 2, 2, 2, 2,
                                             2, 2, 1, 1, 1, 1, 1, 0, 0, 0};
  EXPECT_EQ(reported, expected);
  EXPECT_EQ(tracker.born(), 2u);
}

TEST(TrackerTest, ATrackIsBornWithItsObservationsOfTheFramesBefore) {
  // A from frame 0, B from frame 1 listed first: each is born in its third frame, naming
  // where it was in the two before; later frames name none.
  Tracker tracker(threeHits());
  std::vector<std::vector<EarlierObservation>> earlier_a, earlier_b;
  for (int k = 0; k < 5; ++k) {
    std::vector<Observation> frame;
    if (k >= 1) frame.push_back(car(-10.0, 5.0));
    frame.push_back(car(10.0, 0.0));
    for (const Track& track : tracker.update(k * kPeriod, frame)) {
      (track.observation == frame.size() - 1 ? earlier_a : earlier_b)
          .push_back(track.earlier_observations);
    }
  }
  using Earlier = std::vector<EarlierObservation>;
  // (frames before the birth, index in that frame)
  EXPECT_EQ(earlier_a, (std::vector<Earlier>{{{2, 0}, {1, 1}}, {}, {}}));  // born in frame 2
  EXPECT_EQ(earlier_b, (std::vector<Earlier>{{{2, 0}, {1, 0}}, {}}));      // born in frame 3
}

// A car driving along x at 2 m/s, seen in the frames of `seen` among `frames`: per frame the
// first track's id (0: none out), the tracker's tentativeReach(), and the last earlier
// observations a track out named.
struct CarSeenIn {
  std::vector<std::uint32_t> ids;
  std::vector<std::size_t> reach;
  std::vector<EarlierObservation> earlier;
};

CarSeenIn trackCarSeenIn(const TrackingConfig& config, int frames, const std::vector<int>& seen) {
  Tracker tracker(config);
  CarSeenIn run;
  for (int k = 0; k < frames; ++k) {
    std::vector<Observation> frame;
    if (std::find(seen.begin(), seen.end(), k) != seen.end()) {
      frame.push_back(car(10.0 + 0.2 * k, 4.0));
    }
    const std::vector<Track> tracks = tracker.update(k * kPeriod, frame);
    run.ids.push_back(tracks.empty() ? 0 : tracks[0].id);
    run.reach.push_back(tracker.tentativeReach());
    if (!tracks.empty() && !tracks[0].earlier_observations.empty()) {
      run.earlier = tracks[0].earlier_observations;
    }
  }
  return run;
}

TEST(TrackerTest, ATentativeTrackMayMissBirthMissesFramesBeforeItsBirth) {
  // A car seen in frames 0, 1 and 3 (its segment lost in frame 2): with birth_misses 1 it is
  // born in frame 3, naming its cuboids of frames 0 and 1; with 0 its track restarts in frame
  // 3 and is born in frame 5. One seen every other frame is never born with 1.
  const auto run = [](std::size_t birth_misses, const std::vector<int>& seen) {
    TrackingConfig config = threeHits();
    config.birth_misses = birth_misses;
    return trackCarSeenIn(config, 7, seen);
  };
  const std::vector<int> lost_once = {0, 1, 3, 4, 5, 6};
  const CarSeenIn missed = run(1, lost_once);
  EXPECT_EQ(missed.ids, (std::vector<std::uint32_t>{0, 0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(missed.earlier, (std::vector<EarlierObservation>{{3, 0}, {2, 0}}));
  EXPECT_EQ(run(0, lost_once).ids, (std::vector<std::uint32_t>{0, 0, 0, 0, 0, 1, 1}));
  EXPECT_EQ(run(1, {0, 2, 4, 6}).ids, (std::vector<std::uint32_t>(7, 0)));
}

TEST(TrackerTest, ATrackBornAfterItsFirstRunEndedNamesThatRunsFramesWithBackfillGap) {
  // A car seen in frames 0 and 1, lost in frame 2, then seen from frame 3 on: its first run
  // ends in frame 2 (birth_misses 0) and its track is born in frame 5, as without back-fill.
  // With backfill_gap 1 the track started in frame 3 takes the ended run's frames, and is
  // born naming frames 0, 1, 3 and 4; with 0 only 3 and 4. A car seen in frames 0 and 1 only
  // is never born, with or without: nothing names its frames.
  const auto run = [](std::size_t backfill_gap, const std::vector<int>& seen) {
    TrackingConfig config = threeHits();
    config.backfill_gap = backfill_gap;
    const CarSeenIn tracked = trackCarSeenIn(config, 8, seen);
    return std::make_tuple(tracked.ids, tracked.earlier, tracked.reach);
  };
  const std::vector<int> lost_once = {0, 1, 3, 4, 5, 6, 7};
  const std::vector<std::uint32_t> born_in_5 = {0, 0, 0, 0, 0, 1, 1, 1};
  const auto [ids, earlier, reach] = run(1, lost_once);
  EXPECT_EQ(ids, born_in_5);
  EXPECT_EQ(earlier, (std::vector<EarlierObservation>{{5, 0}, {4, 0}, {2, 0}, {1, 0}}));
  // Frame 0 held until the birth: 0, 1 and 2 frames back, then 3 and 4 through the new track.
  EXPECT_EQ(reach, (std::vector<std::size_t>{0, 1, 2, 3, 4, 0, 0, 0}));
  const auto [ids_without, earlier_without, reach_without] = run(0, lost_once);
  EXPECT_EQ(ids_without, born_in_5);
  EXPECT_EQ(earlier_without, (std::vector<EarlierObservation>{{2, 0}, {1, 0}}));
  EXPECT_EQ(reach_without, (std::vector<std::size_t>{0, 1, 0, 0, 1, 0, 0, 0}));
  const auto [ids_twice, earlier_twice, reach_twice] = run(1, {0, 1});
  EXPECT_EQ(ids_twice, std::vector<std::uint32_t>(8, 0));
  EXPECT_TRUE(earlier_twice.empty());
  // Kept through frame 2 (one miss after its run ended), gone in frame 3.
  EXPECT_EQ(reach_twice, (std::vector<std::size_t>{0, 1, 2, 0, 0, 0, 0, 0}));
}

TEST(TrackerTest, EstimatesTheVelocityAndPointsTheYawAlongIt) {
  Tracker tracker(threeHits());
  std::vector<Track> tracks;
  for (int k = 0; k < 30; ++k) {
    // Moving at (3, -4) m/s; the cuboids say yaw + pi (their front is not known).
    const double heading = std::atan2(-4.0, 3.0);
    tracks = tracker.update(k * kPeriod, {car(20.0 + 0.3 * k, 5.0 - 0.4 * k, heading + M_PI)});
  }
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_NEAR(tracks[0].velocity.x(), 3.0, 0.05);
  EXPECT_NEAR(tracks[0].velocity.y(), -4.0, 0.05);
  EXPECT_NEAR(tracks[0].box.yaw(), std::atan2(-4.0, 3.0), 1e-6);
  EXPECT_NEAR(tracks[0].box.centre().x(), 20.0 + 0.3 * 29, 0.01);
}

TEST(TrackerTest, YawIsSmoothedModuloHalfATurn) {
  // A parked car whose cuboid's front flips every frame: the yaw stays 0.05 rad modulo pi
  // (an average of 0.05 and pi + 0.05 would turn the car across its lane).
  Tracker tracker(threeHits());
  std::vector<Track> tracks;
  for (int k = 0; k < 10; ++k) {
    tracks = tracker.update(k * kPeriod, {car(8.0, 2.0, 0.05 + (k % 2) * M_PI)});
  }
  ASSERT_EQ(tracks.size(), 1u);
  const double yaw = tracks[0].box.yaw();
  EXPECT_NEAR(yaw - M_PI * std::round(yaw / M_PI), 0.05, 1e-9);
  EXPECT_NEAR(tracks[0].box.size().x(), 4.5, 1e-9);
}

TEST(TrackerTest, TheYawIsTheMedianOfTheLatestCuboidsYaws) {
  // A parked car whose first cuboid was fitted 60 degrees off, then right (0), one cuboid 40
  // degrees off in frame 6 and one flipped end to end in frame 8: born in frame 2 with the
  // yaw of the two right ones, it keeps 0 throughout (a running average would have been
  // 60 x (1 - gain)^2 off at birth).
  Tracker tracker(threeHits());
  const double degree = M_PI / 180.0;
  for (int k = 0; k < 10; ++k) {
    const double yaw = k == 0 ? 60 * degree : k == 6 ? 40 * degree : k == 8 ? M_PI : 0.0;
    const std::vector<Track> tracks = tracker.update(k * kPeriod, {car(12.0, -3.0, yaw)});
    if (k < 2) {
      continue;
    }
    ASSERT_EQ(tracks.size(), 1u) << "frame " << k;
    const double track_yaw = tracks[0].box.yaw();
    EXPECT_NEAR(track_yaw - M_PI * std::round(track_yaw / M_PI), 0.0, 1e-12) << "frame " << k;
  }
}

TEST(TrackerTest, ACuboidIsTurnedToItsTracksYawByAtMostTheMaxTurn) {
  // The track's yaw is 0: a cuboid 15 degrees off is turned back by 15 degrees, one 30
  // degrees off (more than max_turn_deg 20 from it) is left as fitted, and one flipped end to
  // end and 15 degrees off is turned by 15 degrees, its front kept.
  const Track track{1, car(10.0, 0.0).box};
  const double degree = M_PI / 180.0;
  const auto turn = [&](double yaw) {
    const Eigen::AngleAxisd turned(turnToTrack(track, car(10.0, 0.0, yaw).box, 20.0));
    return turned.angle() * turned.axis().z() / degree;
  };
  EXPECT_NEAR(turn(15 * degree), -15.0, 1e-9);
  EXPECT_NEAR(turn(-15 * degree), 15.0, 1e-9);
  EXPECT_NEAR(turn(30 * degree), 0.0, 1e-9);
  EXPECT_NEAR(turn(M_PI + 15 * degree), -15.0, 1e-9);
}

TEST(TrackerTest, ANeighbourInTheNextLaneDoesNotTakeOverATrack) {
  // A parks at y = 0 for five frames and is gone; B, parked beside it 1.95 m away (within
  // the 2 m distance gate, footprints apart), is seen from then on: a new track, not A's.
  const auto run = [](double min_overlap) {
    TrackingConfig config = threeHits();
    config.gate.min_overlap = min_overlap;
    Tracker tracker(config);
    std::vector<std::uint32_t> ids;
    for (int k = 0; k < 12; ++k) {
      const std::vector<Track> tracks =
          tracker.update(k * kPeriod, {k < 5 ? car(10.0, 0.0) : car(10.0, 1.95)});
      ids.push_back(idOf(tracks, 0));
    }
    return ids;
  };
  EXPECT_EQ(run(0.1), (std::vector<std::uint32_t>{0, 0, 1, 1, 1, 0, 0, 2, 2, 2, 2, 2}));
  // With the distance alone, B would continue A's track.
  EXPECT_EQ(run(0.0), (std::vector<std::uint32_t>{0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1}));
}

TEST(TrackerTest, AParkedRowKeepsItsIdsWhenACarLeavesOneEndAndOneComesInAtTheOther) {
  // Seven cars parked 2.6 m apart along x, passed by the sensor at 1 m/s (the parking lot):
  // frame 0 sees cars 0 to 5, and from frame 1 on car 0 is behind the sensor and car 6 comes
  // into view. A track seen once has no velocity yet and a gate wider than the spacing
  // (about 3.3 m), so shifting every track one car along would pair all six; the least cost
  // leaves car 0's track without a cuboid instead, and each car keeps its own track.
  Tracker tracker(threeHits());
  std::vector<std::vector<std::uint32_t>> ids;  // per frame, by car
  for (int k = 0; k < 8; ++k) {
    std::vector<Observation> frame;
    for (int c = k == 0 ? 0 : 1; c <= (k == 0 ? 5 : 6); ++c) {
      frame.push_back(car(2.6 * c - 0.1 * k, -6.0, M_PI / 2));
    }
    const std::vector<Track> tracks = tracker.update(k * kPeriod, frame);
    std::vector<std::uint32_t> frame_ids;
    for (std::size_t o = 0; o < frame.size(); ++o) {
      frame_ids.push_back(idOf(tracks, o));
    }
    ids.push_back(frame_ids);
  }
  // Cars 1 to 5 born in frame 2 as tracks 1 to 5, car 6 (first seen in frame 1) in frame 3;
  // car 0, seen once, never.
  EXPECT_EQ(ids[2], (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 0}));
  for (int k = 3; k < 8; ++k) {
    EXPECT_EQ(ids[k], (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6})) << "frame " << k;
  }
  EXPECT_EQ(tracker.born(), 6u);
}

TEST(TrackerTest, ABornTrackTakesItsCuboidBeforeATentativeOneNearer) {
  // Track 1 follows a parked car at x = 10 (born in frame 2). In frame 4 a piece 2 m beyond it
  // starts a tentative track; in frame 5 the car's cuboid has moved its centre to 11.2 (the
  // view changed), 0.8 m from the piece's place and 1.2 m from the track's: the born track
  // takes it, where the least cost over all tracks together would give it to the piece's.
  Tracker tracker(threeHits());
  std::vector<Track> tracks;
  for (int k = 0; k < 4; ++k) {
    tracks = tracker.update(k * kPeriod, {car(10.0, 0.0)});
  }
  tracks = tracker.update(4 * kPeriod, {car(10.0, 0.0), car(12.0, 0.0)});
  EXPECT_EQ(idOf(tracks, 0), 1u);
  tracks = tracker.update(5 * kPeriod, {car(11.2, 0.0)});
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(idOf(tracks, 0), 1u);
  EXPECT_EQ(tracks[0].misses, 0u);
}

TEST(TrackerTest, ATrackSeenOnceDoesNotStepSidewaysAlongAParkedRow) {
  // Each frame one cuboid of a different car of a row parked along y, 2.6 m apart (the
  // others missed): a chain a track seen once could follow within its widened gate, 26 m/s
  // across the cars' length axis. With max_sideways no track is born of it; without, one is.
  const auto born = [](double max_sideways) {
    TrackingConfig config = threeHits();
    config.gate.max_sideways = max_sideways;
    Tracker tracker(config);
    for (int k = 0; k < 6; ++k) {
      tracker.update(k * kPeriod, {car(2.6 * k, -6.0, M_PI / 2)});
    }
    return tracker.born();
  };
  EXPECT_EQ(born(1.0), 0u);
  EXPECT_EQ(born(10.0), 1u);
}

TEST(TrackerTest, AFastCarIsFollowedFromItsSecondFrameOn) {
  // Oncoming at 22 m/s relative to the sensor, 5 frames a second: 4.4 m a frame, beyond the
  // 2 m gate, but a track seen once has no velocity yet and its gate is 3 standard deviations
  // of the unknown velocity's reach (10 m/s x 0.2 s, about 6 m).
  Tracker tracker(threeHits());
  std::vector<Track> tracks;
  for (int k = 0; k < 8; ++k) {
    tracks = tracker.update(k * 0.2, {car(40.0 - 4.4 * k, 3.5, M_PI)});
  }
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].id, 1u);
  EXPECT_EQ(tracks[0].observation, 0u);
  EXPECT_EQ(tracks[0].hits, 8u);
  EXPECT_NEAR(tracks[0].velocity.x(), -22.0, 0.5);
  EXPECT_EQ(tracker.born(), 1u);
}

TEST(TrackerTest, AJumpBeyondTheDistanceGateStartsANewTrack) {
  Tracker tracker(threeHits());
  std::vector<Track> tracks;
  for (int k = 0; k < 4; ++k) {
    tracks = tracker.update(k * kPeriod, {car(10.0, 0.0)});
  }
  tracks = tracker.update(0.4, {car(10.0, 2.5)});  // 2.5 m off a parked car's place
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_FALSE(tracks[0].observation);
  EXPECT_EQ(tracks[0].misses, 1u);
}

TEST(TrackerTest, RefusesStampsThatDoNotMoveOnAndBadConfigs) {
  Tracker tracker(threeHits());
  tracker.update(1.0, {});
  EXPECT_THROW(tracker.update(1.0, {}), std::invalid_argument);
  EXPECT_THROW(tracker.update(0.5, {}), std::invalid_argument);
  EXPECT_THROW(tracker.update(std::nan(""), {}), std::invalid_argument);
  TrackingConfig config;
  config.birth_hits = 0;
  EXPECT_THROW(Tracker{config}, std::invalid_argument);
}

}  // namespace
}  // namespace granular
