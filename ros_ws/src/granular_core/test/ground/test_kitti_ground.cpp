// Golden test on real LiDAR data: the road plane of the ten KITTI fixture frames against the
// planes published with them (fitted by the AVOD authors in the camera's view), and against
// the road returns themselves.
//
// The published planes are a reference good to a few centimetres only: the roads are not
// planar, and in front of the car the LiDAR's own road returns lie up to 4 cm above them
// (frame 000007: a median of +4.2 cm within 3-10 m; docs/ground.md). So the height
// under the sensor may differ from the published plane by 6 cm, and the plane must sit on the
// road returns near the vehicle within 3 cm (their median height above it; one plane cannot
// follow a road that bends, as frame 000003's does by about 2.5 cm).
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/ground/ground.h"
#include "support/kitti.h"

namespace granular {
namespace {

// The median height above `plane` of the returns in front, 3 to 20 m away, within 0.15 m of
// it: the road the vehicle is about to drive on.
double medianRoadHeight(const Cloud& cloud, const GroundPlane& plane) {
  std::vector<double> heights;
  for (const PointXYZIT& point : cloud.points) {
    const double range = std::hypot(point.x, point.y);
    const double height = plane.heightOf(point.getVector3fMap().cast<double>());
    if (point.x > 0 && std::abs(point.y) < point.x && range > 3.0 && range < 20.0 &&
        std::abs(height) < 0.15) {
      heights.push_back(height);
    }
  }
  std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
  return heights[heights.size() / 2];
}

TEST(KittiGroundTest, EachFramesPlaneMatchesThePublishedPlaneAndTheRoadReturns) {
  if (!std::filesystem::is_directory(testing_kitti::kFixture)) {
    GTEST_SKIP() << "KITTI fixture not found at " << testing_kitti::kFixture;
  }
  for (int index = 0; index < 10; ++index) {
    char frame[8];
    std::snprintf(frame, sizeof(frame), "%06d", index);
    SCOPED_TRACE(std::string("frame ") + frame);
    const Cloud cloud = testing_kitti::readVelodyne(testing_kitti::kFixture / "velodyne" /
                                                    (std::string(frame) + ".bin"));
    const auto [normal, offset] = testing_kitti::roadPlane(frame);
    std::size_t inliers = 0;
    const GroundPlane plane = estimateGroundPlane(cloud, GroundPlaneConfig(), nullptr, &inliers);
    const double angle = std::acos(std::min(1.0, plane.normal.dot(normal))) * 180.0 / M_PI;
    const double height = plane.zUnderSensor() - (-offset / normal.z());
    const double road = medianRoadHeight(cloud, plane);
    EXPECT_LT(angle, 1.0);
    EXPECT_LT(std::abs(height), 0.06);
    EXPECT_LT(std::abs(road), 0.03);
    // A real sensor-frame cloud is never taken for a world frame.
    EXPECT_EQ(checkGround(cloud, plane, inliers, GroundConfig(), "velodyne").verdict,
              GroundCheck::Verdict::kGround);
    std::printf("[ frame %s ] angle %.2f deg, height %+.3f m, road returns %+.3f m\n", frame,
                angle, height, road);
  }
}

}  // namespace
}  // namespace granular
