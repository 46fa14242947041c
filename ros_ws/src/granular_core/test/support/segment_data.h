// Segments of simulated clouds kept in test/data as text: x y (m, sensor frame) and height
// above the road (m), one return a line, '#' lines comments.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace granular {
namespace testing_support {

// The returns of test/data/`name` as (x, y, height above the road).
inline std::vector<Eigen::Vector3d> segmentOnRoad(const std::string& name) {
  std::ifstream file(std::string(GRANULAR_CORE_TEST_DATA) + "/" + name);
  EXPECT_TRUE(file) << "test data missing: " << name;
  std::vector<Eigen::Vector3d> points;
  std::string line;
  while (std::getline(file, line)) {
    std::istringstream fields(line);
    double x, y, height;
    if (line[0] != '#' && fields >> x >> y >> height) {
      points.emplace_back(x, y, height);
    }
  }
  return points;
}

}  // namespace testing_support
}  // namespace granular
