// Golden test on real LiDAR data: the box-free segmentation on the ten KITTI fixture frames,
// against their labels. Every labelled object of at least 10 points gets a segment whose
// centre lies in its footprint (docs/segmentation.md: 21 of 22 before walls were peeled off,
// the miss the Misc object of frame 000002, merged with the wall it stands against).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/geometry/oriented_box.h"
#include "granular_core/segmentation/object_segmentation.h"
#include "support/kitti.h"

namespace granular {
namespace {

// The frame's labels (DontCare skipped) holding at least `min_points` of its points.
std::vector<OrientedBox> labelledObjects(const std::string& frame, const Cloud& cloud,
                                         std::size_t min_points) {
  const Eigen::Affine3d to_rect =
      testing_kitti::veloToRect(testing_kitti::kFixture / "calib" / (frame + ".txt"));
  std::ifstream labels(testing_kitti::kFixture / "label_2" / (frame + ".txt"));
  std::vector<OrientedBox> objects;
  for (std::string line; std::getline(labels, line);) {
    if (line.empty() || line.rfind("DontCare", 0) == 0) {
      continue;
    }
    const Detection label = testing_kitti::labelToDetection(line, to_rect);
    const OrientedBox box(label.centre, label.orientation, label.size);
    const Eigen::Isometry3d to_object = box.sensorToObject();  // origin on the bottom face
    std::size_t inside = 0;
    for (const PointXYZIT& point : cloud.points) {
      const Eigen::Vector3d local = to_object * point.getVector3fMap().cast<double>();
      inside += std::abs(local.x()) <= box.size().x() / 2 &&
                std::abs(local.y()) <= box.size().y() / 2 && local.z() >= 0 &&
                local.z() <= box.size().z();
    }
    if (inside >= min_points) {
      objects.push_back(box);
    }
  }
  return objects;
}

// Whether a segment's box centre lies in the object's footprint, seen from above.
bool inFootprint(const Segment& segment, const OrientedBox& object) {
  const Eigen::Vector2d offset =
      Eigen::Rotation2Dd(-object.yaw()) * (segment.box.centre() - object.centre()).head<2>();
  return std::abs(offset.x()) <= object.size().x() / 2 &&
         std::abs(offset.y()) <= object.size().y() / 2;
}

TEST(KittiSegmentationTest, EveryLabelledObjectHasASegmentInItsFootprint) {
  if (!std::filesystem::is_directory(testing_kitti::kFixture)) {
    GTEST_SKIP() << "KITTI fixture not found at " << testing_kitti::kFixture;
  }
  ObjectSegmentationConfig no_peeling;
  no_peeling.walls.max_walls = 0;
  std::size_t objects = 0, found = 0, found_without_peeling = 0;
  for (int index = 0; index < 10; ++index) {
    char frame[8];
    std::snprintf(frame, sizeof(frame), "%06d", index);
    const Cloud cloud = testing_kitti::readVelodyne(testing_kitti::kFixture / "velodyne" /
                                                    (std::string(frame) + ".bin"));
    const std::vector<Segment> segments = segmentObjects(cloud).segments;
    const std::vector<Segment> unpeeled = segmentObjects(cloud, {}, no_peeling).segments;
    for (const OrientedBox& object : labelledObjects(frame, cloud, 10)) {
      ++objects;
      const auto hit = [&](const std::vector<Segment>& all) {
        return std::any_of(all.begin(), all.end(),
                           [&](const Segment& segment) { return inFootprint(segment, object); });
      };
      EXPECT_TRUE(hit(segments)) << "frame " << frame << ": the object at ("
                                 << object.centre().x() << ", " << object.centre().y() << ")";
      found += hit(segments);
      found_without_peeling += hit(unpeeled);
    }
  }
  EXPECT_EQ(objects, 22u);
  EXPECT_EQ(found, 22u);
  EXPECT_EQ(found_without_peeling, 21u);  // the Misc against its wall
}

}  // namespace
}  // namespace granular
