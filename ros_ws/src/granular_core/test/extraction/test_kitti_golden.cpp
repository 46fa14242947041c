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

namespace granular {
namespace {

namespace fs = std::filesystem;

const fs::path kFixture = GRANULAR_KITTI_FIXTURE_DIR;

// The oracle applies R0_rect * Tr_velo_to_cam, which is not exactly a rotation, to the points;
// here its closest rigid motion is applied to the box instead. The two differ by millimetres at
// the box faces, so points lying on a face can fall either way: allow 2 points or 2%.
bool closeToOracle(std::size_t count, std::size_t oracle) {
  const double allowed = std::max(2.0, 0.02 * static_cast<double>(oracle));
  return std::abs(static_cast<double>(count) - static_cast<double>(oracle)) <= allowed;
}

std::vector<double> calibrationRow(const fs::path& file, const std::string& key) {
  std::ifstream stream(file);
  std::string line;
  while (std::getline(stream, line)) {
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream values(line.substr(key.size() + 1));
      std::vector<double> row;
      for (double value; values >> value;) {
        row.push_back(value);
      }
      return row;
    }
  }
  ADD_FAILURE() << file << " has no " << key;
  return {};
}

// LiDAR -> rectified camera, as one affine map.
Eigen::Affine3d veloToRect(const fs::path& calibration) {
  const std::vector<double> r0 = calibrationRow(calibration, "R0_rect");
  const std::vector<double> tr = calibrationRow(calibration, "Tr_velo_to_cam");
  EXPECT_EQ(r0.size(), 9u);
  EXPECT_EQ(tr.size(), 12u);
  Eigen::Affine3d rect = Eigen::Affine3d::Identity();
  Eigen::Affine3d velo_to_cam = Eigen::Affine3d::Identity();
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      rect.linear()(row, column) = r0[row * 3 + column];
      velo_to_cam.linear()(row, column) = tr[row * 4 + column];
    }
    velo_to_cam.translation()[row] = tr[row * 4 + 3];
  }
  return rect * velo_to_cam;
}

Cloud readVelodyne(const fs::path& file) {
  std::ifstream stream(file, std::ios::binary);
  Cloud cloud;
  float values[4];  // x, y, z, reflectance
  while (stream.read(reinterpret_cast<char*>(values), sizeof(values))) {
    cloud.push_back(PointXYZIT(values[0], values[1], values[2], 0, 0.0));
  }
  return cloud;
}

// A KITTI label line as a LiDAR-frame detection. KITTI gives h w l, the bottom centre (x, y, z)
// in the rectified camera frame (y down) and rotation_y about the camera y axis.
Detection labelToDetection(const std::string& line, const Eigen::Affine3d& velo_to_rect) {
  std::istringstream fields(line);
  std::string label;
  double ignored, h, w, l, x, y, z, rotation_y;
  fields >> label;
  for (int i = 0; i < 7; ++i) {
    fields >> ignored;
  }
  fields >> h >> w >> l >> x >> y >> z >> rotation_y;
  EXPECT_FALSE(fields.fail()) << line;

  const Eigen::Matrix3d about_y =
      Eigen::AngleAxisd(rotation_y, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Matrix3d box_axes_in_rect;
  box_axes_in_rect.col(0) = about_y * Eigen::Vector3d::UnitX();  // length
  box_axes_in_rect.col(2) = -Eigen::Vector3d::UnitY();            // up
  box_axes_in_rect.col(1) = box_axes_in_rect.col(2).cross(box_axes_in_rect.col(0));

  const Eigen::Affine3d rect_to_velo = velo_to_rect.inverse();
  Detection detection;
  detection.label = label;
  detection.centre = rect_to_velo * Eigen::Vector3d(x, y - h / 2.0, z);
  // Quaterniond(Matrix3d) of the almost-rotation keeps its rotational part; the box normalises.
  detection.orientation = Eigen::Quaterniond(rect_to_velo.linear() * box_axes_in_rect);
  detection.size = Eigen::Vector3d(l, w, h);
  return detection;
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
