// The Background class: which segments of a labelled frame lie on no labelled object.
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/segmentation/background.h"

namespace granular {
namespace {

// A car's true box 10 m ahead: 4 x 2 x 1.5 m, its bottom 1.7 m below the sensor.
OrientedBox trueCar() {
  return OrientedBox(Eigen::Vector3d(10.0, 0.0, -0.95), Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d(4.0, 2.0, 1.5));
}

// A segment of `count` points in a row along y starting at (x, y0), 0.1 m apart, 1 m above
// the road; its box is a unit box around the first point (only the centre matters here).
Segment row(Cloud& cloud, double x, double y0, int count) {
  Segment segment{OrientedBox(Eigen::Vector3d(x, y0, -0.7), Eigen::Quaterniond::Identity(),
                              Eigen::Vector3d::Ones()),
                  {}, 1};
  for (int i = 0; i < count; ++i) {
    segment.indices.push_back(cloud.size());
    cloud.push_back(PointXYZIT(static_cast<float>(x), static_cast<float>(y0 + 0.1 * i), -0.7f,
                               0, 0.0));
  }
  return segment;
}

// The indices of the segments labelSegments calls background, in order.
std::vector<std::size_t> backgroundSegments(const Cloud& cloud,
                                            const std::vector<Segment>& segments,
                                            const std::vector<OrientedBox>& truth,
                                            const BackgroundConfig& config = {}) {
  std::vector<std::size_t> background;
  for (const LabelledSegment& segment : labelSegments(cloud, segments, truth, config)) {
    if (!segment.truth) {
      background.push_back(segment.segment);
    }
  }
  return background;
}

TEST(BackgroundTest, SegmentsOffEveryTrueBoxAreBackgroundAndOnesOnABoxAreNot) {
  Cloud cloud;
  const std::vector<Segment> segments = {
      row(cloud, 10.0, -0.5, 10),  // on the car
      row(cloud, 20.0, 5.0, 10),   // a wall far from it
      row(cloud, 9.0, -0.8, 20),   // across the car, y up to 1.1 m
  };
  EXPECT_EQ(backgroundSegments(cloud, segments, {trueCar()}), (std::vector<std::size_t>{1}));
  // With no labels in the frame every segment is background.
  EXPECT_EQ(backgroundSegments(cloud, segments, {}), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(BackgroundTest, SegmentsAreLabelledByTheTrueBoxHoldingMostOfThem) {
  Cloud cloud;
  // A second car beside the first: y 2.2 to 4.2, grown by the margin 1.9 to 4.5.
  const OrientedBox second_car(Eigen::Vector3d(10.0, 3.2, -0.95), Eigen::Quaterniond::Identity(),
                               Eigen::Vector3d(4.0, 2.0, 1.5));
  const std::vector<Segment> segments = {
      row(cloud, 10.0, 2.5, 10),   // on the second car
      row(cloud, 20.0, 5.0, 10),   // a wall
      row(cloud, 10.0, -0.5, 10),  // on the first car
      row(cloud, 10.0, 0.95, 10),  // y 0.95 to 1.85: 4 points on the first car (y <= 1.3)
  };
  const std::vector<LabelledSegment> labelled =
      labelSegments(cloud, segments, {trueCar(), second_car});
  ASSERT_EQ(labelled.size(), 3u);  // the last is neither background nor one car's
  EXPECT_EQ(labelled[0].segment, 0u);
  EXPECT_EQ(labelled[0].truth, std::optional<std::size_t>(1));
  EXPECT_EQ(labelled[1].segment, 1u);
  EXPECT_FALSE(labelled[1].truth);
  EXPECT_EQ(labelled[2].segment, 2u);
  EXPECT_EQ(labelled[2].truth, std::optional<std::size_t>(0));
  BackgroundConfig config;
  config.min_object_share = 0.3;  // 4 of 10 on the first car is enough now
  const std::vector<LabelledSegment> looser =
      labelSegments(cloud, segments, {trueCar(), second_car}, config);
  ASSERT_EQ(looser.size(), 4u);
  EXPECT_EQ(looser[3].truth, std::optional<std::size_t>(0));
}

TEST(BackgroundTest, TheShareOnObjectsDecides) {
  Cloud cloud;
  // 20 points from y = 0.85: y <= 1.3 (the car's half width 1 m grown by 0.3 m) holds the
  // first 5 of them, a quarter.
  const std::vector<Segment> segments = {row(cloud, 10.0, 0.85, 20)};
  BackgroundConfig config;
  EXPECT_TRUE(backgroundSegments(cloud, segments, {trueCar()}, config).empty());
  config.max_object_share = 0.3;
  EXPECT_EQ(backgroundSegments(cloud, segments, {trueCar()}, config).size(), 1u);
  config.max_object_share = 0.1;
  config.margin = 0.0;  // y <= 1.0: 2 points of 20 on the car, 0.1
  EXPECT_EQ(backgroundSegments(cloud, segments, {trueCar()}, config).size(), 1u);
}

TEST(BackgroundTest, OnlyTheLabelledViewAndRangeAreHarvested) {
  Cloud cloud;
  const std::vector<Segment> segments = {
      row(cloud, -15.0, 0.0, 10),  // behind the sensor
      row(cloud, 15.0, 20.0, 10),  // 53 deg to the left
      row(cloud, 90.0, 0.0, 10),   // beyond 80 m
      row(cloud, 30.0, 5.0, 10),   // ahead
  };
  BackgroundConfig config;
  config.half_field_of_view_deg = 40.0;
  EXPECT_EQ(backgroundSegments(cloud, segments, {}, config), (std::vector<std::size_t>{3}));
}

TEST(BackgroundTest, OnlyASureEnoughBackgroundAnswerDropsASegment) {
  BackgroundConfig config;  // min_score 1: the SVM's answer won every duel
  EXPECT_TRUE(calledBackground("Background", 1.0, 50, 10.0, config));
  EXPECT_FALSE(calledBackground("Background", 6.0 / 7.0, 50, 10.0, config));
  EXPECT_FALSE(calledBackground("Sedan", 1.0, 50, 10.0, config));
  config.min_score = 0.5;
  EXPECT_TRUE(calledBackground("Background", 6.0 / 7.0, 50, 10.0, config));
  config.label = "Clutter";
  EXPECT_FALSE(calledBackground("Background", 1.0, 50, 10.0, config));
}

TEST(BackgroundTest, TheDecisionAbstainsOnlyOnFarSparseSegments) {
  BackgroundConfig config;  // fewer than 20 points beyond 30 m: kept
  EXPECT_FALSE(calledBackground("Background", 1.0, 19, 40.0, config));
  EXPECT_TRUE(calledBackground("Background", 1.0, 20, 40.0, config));
  EXPECT_TRUE(calledBackground("Background", 1.0, 19, 25.0, config));  // near: a small thing
  config.abstain_points = 0;
  EXPECT_TRUE(calledBackground("Background", 1.0, 3, 40.0, config));
}

TEST(BackgroundTest, ValidateNamesTheField) {
  BackgroundConfig config;
  config.label = "";
  EXPECT_THROW(validate(config), std::invalid_argument);
  config = BackgroundConfig();
  config.max_object_share = 1.5;
  try {
    validate(config);
    FAIL() << "a share above 1 was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("max_object_share"), std::string::npos);
  }
}

}  // namespace
}  // namespace granular
