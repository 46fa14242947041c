// Golden test on real LiDAR data: KITTI object frames 000000-000002 (kept outside the repository,
// see GRANULAR_KITTI_FIXTURE_DIR). Each camera-frame label is turned into a LiDAR-frame box and
// the core's crop count is compared with the count of the fixture's README, which was made
// independently (points moved into the rectified camera frame, box test there).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/extraction/extract_objects.h"
#include "support/kitti.h"

namespace granular {
namespace {

namespace fs = std::filesystem;
using testing_kitti::kFixture;
using testing_kitti::labelToDetection;
using testing_kitti::readVelodyne;
using testing_kitti::veloToRect;

// The oracle applies R0_rect * Tr_velo_to_cam, which is not exactly a rotation, to the points;
// here its closest rigid motion is applied to the box instead. The two differ by millimetres at
// the box faces, so points lying on a face can fall either way: allow 2 points or 2%.
bool closeToOracle(std::size_t count, std::size_t oracle) {
  const double allowed = std::max(2.0, 0.02 * static_cast<double>(oracle));
  return std::abs(static_cast<double>(count) - static_cast<double>(oracle)) <= allowed;
}

struct OracleCount {
  const char* frame;
  std::size_t line;
  const char* label;
  std::size_t points;
};

// From the fixture's README.md.
const OracleCount kOracle[] = {
    {"000000", 0, "Pedestrian", 376}, {"000001", 0, "Truck", 70}, {"000001", 1, "Car", 9},
    {"000001", 2, "Cyclist", 18},     {"000002", 0, "Misc", 1351}, {"000002", 1, "Car", 67},
};

TEST(KittiGoldenTest, CropCountsMatchTheIndependentCount) {
  if (!fs::is_directory(kFixture)) {
    GTEST_SKIP() << "KITTI fixture not found at " << kFixture;
  }
  for (const OracleCount& oracle : kOracle) {
    SCOPED_TRACE(std::string("frame ") + oracle.frame + " label line " +
                 std::to_string(oracle.line));
    const Eigen::Affine3d velo_to_rect =
        veloToRect(kFixture / "calib" / (std::string(oracle.frame) + ".txt"));
    std::ifstream labels(kFixture / "label_2" / (std::string(oracle.frame) + ".txt"));
    std::string line;
    for (std::size_t i = 0; i <= oracle.line; ++i) {
      ASSERT_TRUE(std::getline(labels, line));
    }
    const Detection detection = labelToDetection(line, velo_to_rect);
    ASSERT_EQ(detection.label, oracle.label);

    const Cloud cloud = readVelodyne(kFixture / "velodyne" / (std::string(oracle.frame) + ".bin"));
    ASSERT_GT(cloud.size(), 100000u);
    const FrameExtraction result = extractObjects(cloud, {detection}, ExtractionConfig());
    ASSERT_EQ(result.objects.size(), 1u);
    const Cloud& object = result.objects[0].cloud;
    EXPECT_TRUE(closeToOracle(object.size(), oracle.points))
        << object.size() << " points, oracle " << oracle.points;

    // In the object frame the points lie inside the KITTI box dimensions.
    for (const PointXYZIT& point : object.points) {
      EXPECT_LE(std::abs(point.x), detection.size.x() / 2 + 1e-4);
      EXPECT_LE(std::abs(point.y), detection.size.y() / 2 + 1e-4);
      EXPECT_GE(point.z, -1e-4);
      EXPECT_LE(point.z, detection.size.z() + 1e-4);
    }
  }
}

}  // namespace
}  // namespace granular
