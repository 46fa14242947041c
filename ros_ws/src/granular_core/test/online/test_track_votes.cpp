// One vote per frame per track: the most frequent label wins, a tie keeps the label held,
// tracks are separate, and a track not seen for a while starts again.
#include <gtest/gtest.h>

#include "granular_core/online/track_votes.h"

namespace granular {
namespace {

TEST(TrackVotesTest, TheMostFrequentLabelWinsAndATieKeepsTheLabelHeld) {
  TrackVotes votes;
  EXPECT_EQ(votes.vote(7, "Sedan", 0.0).label, "Sedan");
  const TrackLabel tie = votes.vote(7, "Hatchback", 0.1);
  EXPECT_EQ(tie.label, "Sedan");  // 1 : 1, the label held
  EXPECT_DOUBLE_EQ(tie.share, 0.5);
  EXPECT_EQ(votes.vote(7, "Sedan", 0.2).label, "Sedan");      // 2 : 1
  EXPECT_EQ(votes.vote(7, "Hatchback", 0.3).label, "Sedan");  // 2 : 2 again
  const TrackLabel settled = votes.vote(7, "Sedan", 0.4);
  EXPECT_EQ(settled.label, "Sedan");
  EXPECT_EQ(settled.votes, 5u);
  EXPECT_DOUBLE_EQ(settled.share, 0.6);
  EXPECT_EQ(votes.vote(7, "Jeep", 0.5).label, "Sedan");       // 3 : 2 : 1
  EXPECT_EQ(votes.vote(7, "Hatchback", 0.6).label, "Sedan");  // 3 : 3 : 1
  const TrackLabel overtaken = votes.vote(7, "Hatchback", 0.7);
  EXPECT_EQ(overtaken.label, "Hatchback");  // 3 : 4 : 1
  EXPECT_DOUBLE_EQ(overtaken.share, 0.5);
}

TEST(TrackVotesTest, VotesWeighedByPointsLetANearFrameOutweighFarOnes) {
  TrackVotes votes;
  for (int frame = 0; frame < 4; ++frame) {  // far: 30 points a frame
    EXPECT_EQ(votes.vote(3, "BoxTruck", 0.1 * frame, 30.0).label, "BoxTruck");
  }
  const TrackLabel near = votes.vote(3, "SchoolBus", 0.4, 200.0);  // 200 against 120
  EXPECT_EQ(near.label, "SchoolBus");
  EXPECT_DOUBLE_EQ(near.share, 200.0 / 320.0);
  EXPECT_EQ(near.votes, 5u);
}

TEST(TrackVotesTest, TracksVoteApart) {
  TrackVotes votes;
  votes.vote(1, "SUV", 0.0);
  votes.vote(1, "SUV", 0.1);
  EXPECT_EQ(votes.vote(2, "Jeep", 0.1).label, "Jeep");
  EXPECT_EQ(votes.vote(1, "Jeep", 0.2).label, "SUV");
  EXPECT_EQ(votes.tracks(), 2u);
}

TEST(TrackVotesTest, ATrackUnseenForLongStartsAgain) {
  TrackVotes votes(2.0);
  votes.vote(1, "SUV", 0.0);
  votes.vote(1, "SUV", 0.1);
  votes.vote(2, "Jeep", 1.5);
  votes.forget(2.5);  // track 1 last seen 2.4 s ago, track 2 1.0 s ago
  EXPECT_EQ(votes.tracks(), 1u);
  EXPECT_EQ(votes.vote(1, "Jeep", 2.5).label, "Jeep");  // id 1 is a new vehicle now
  EXPECT_EQ(votes.vote(2, "SUV", 2.5).label, "Jeep");   // 1 : 1, the label track 2 held
}

}  // namespace
}  // namespace granular
