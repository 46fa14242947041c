// SegmentViews: each segment's points as the fitters see them, with the ground, the height
// cap and the frame's free space for the objects method, and none of them for occupancy.
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/cuboids/segment_views.h"

namespace granular {
namespace {

// A frame: a wall 20 m ahead at body height, and two segments of it; its road 1.7 m below.
class SegmentViewsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int i = 0; i < 5; ++i) {
      cloud_.push_back(PointXYZIT(20.0f, -0.5f + 0.25f * i, -0.7f, 0, 0.0));
    }
    segmentation_.ground.plane.offset = 1.7;
    const OrientedBox box(Eigen::Vector3d(20.0, 0.0, -0.7), Eigen::Quaterniond::Identity(),
                          Eigen::Vector3d(0.2, 1.2, 0.2));
    segmentation_.segments.push_back(Segment{box, {1, 3}, 1});
    segmentation_.segments.push_back(Segment{box, {0, 2, 4}, 1});
  }

  Cloud cloud_;
  ObjectSegmentation segmentation_;
};

TEST_F(SegmentViewsTest, TheObjectsMethodsViewsStandOnTheGroundUnderTheCapBesideFreeSpace) {
  SegmentationStageConfig config;
  config.objects.max_height = 2.8;
  const SegmentViews views(cloud_, segmentation_, config, FreeSpaceConfig());
  const ObjectView view = views.view(0);
  ASSERT_EQ(view.points.size(), 2u);
  EXPECT_EQ(view.points[0], Eigen::Vector3d(20.0, -0.25, -0.7f));
  EXPECT_EQ(view.points[1], Eigen::Vector3d(20.0, 0.25, -0.7f));
  ASSERT_TRUE(view.ground);
  EXPECT_EQ(view.ground->offset, 1.7);
  ASSERT_TRUE(view.height_cap);
  EXPECT_EQ(*view.height_cap, 2.8);
  ASSERT_NE(view.free_space, nullptr);
  // The rays to the wall passed over 10 m ahead at body height; nothing was seen beyond it.
  EXPECT_TRUE(view.free_space->seenEmpty(Eigen::Vector3d(10.0, 0.0, -0.7)));
  EXPECT_FALSE(view.free_space->seenEmpty(Eigen::Vector3d(25.0, 0.0, -0.7)));
  EXPECT_EQ(views.view(1).points.size(), 3u);
  EXPECT_EQ(views.view(1).free_space, view.free_space);  // one per frame, shared
}

TEST_F(SegmentViewsTest, TheOccupancyMethodsViewsAreThePointsAlone) {
  SegmentationStageConfig config;
  config.method = SegmentationMethod::kOccupancy;
  const SegmentViews views(cloud_, segmentation_, config, FreeSpaceConfig());
  const ObjectView view = views.view(1);
  ASSERT_EQ(view.points.size(), 3u);
  EXPECT_EQ(view.points[2], Eigen::Vector3d(20.0, 0.5, -0.7f));
  EXPECT_FALSE(view.ground);
  EXPECT_FALSE(view.height_cap);
  EXPECT_EQ(view.free_space, nullptr);
}

}  // namespace
}  // namespace granular
