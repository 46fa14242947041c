// KITTI's object-benchmark files for the golden tests: calibration, Velodyne clouds, labels as
// LiDAR-frame detections and the published road planes. The sample lives beside the
// repository (GRANULAR_KITTI_FIXTURE_DIR), never inside it.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "granular_core/dataset/detections.h"
#include "granular_core/point_types.h"

namespace granular {
namespace testing_kitti {

namespace fs = std::filesystem;

inline const fs::path kFixture = GRANULAR_KITTI_FIXTURE_DIR;

inline std::vector<double> calibrationRow(const fs::path& file, const std::string& key) {
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
inline Eigen::Affine3d veloToRect(const fs::path& calibration) {
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

inline Cloud readVelodyne(const fs::path& file) {
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
inline Detection labelToDetection(const std::string& line, const Eigen::Affine3d& velo_to_rect) {
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

// The published road plane of a frame in the LiDAR frame: unit normal up, and offset.
inline std::pair<Eigen::Vector3d, double> roadPlane(const std::string& frame) {
  std::ifstream stream(kFixture / "planes" / (frame + ".txt"));
  std::string line, last;
  while (std::getline(stream, line)) {
    if (!line.empty() && line[0] != '#') {
      last = line;
    }
  }
  std::istringstream values(last);
  Eigen::Vector3d normal;
  double offset = 0.0;
  values >> normal.x() >> normal.y() >> normal.z() >> offset;
  EXPECT_FALSE(values.fail()) << frame << ": no plane";
  // rect: n . p_rect + d = 0 with p_rect = A p + t, so (A^T n) . p + (n . t + d) = 0.
  const Eigen::Affine3d to_rect = veloToRect(kFixture / "calib" / (frame + ".txt"));
  Eigen::Vector3d velo_normal = to_rect.linear().transpose() * normal;
  double velo_offset = normal.dot(to_rect.translation()) + offset;
  const double length = velo_normal.norm();
  velo_normal /= length;
  velo_offset /= length;
  if (velo_normal.z() < 0.0) {
    velo_normal = -velo_normal;
    velo_offset = -velo_offset;
  }
  return {velo_normal, velo_offset};
}

}  // namespace testing_kitti
}  // namespace granular
