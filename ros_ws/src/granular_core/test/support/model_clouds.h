// Synthetic clouds shared by the model tests.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "granular_core/point_types.h"

namespace granular {
namespace testing_clouds {

// `count` points uniformly on the faces of the box [-L/2, L/2] x [-W/2, W/2] x [0, H] (no
// bottom face: the road), each face getting points in proportion to its area.
inline ModelCloud boxSurface(const Eigen::Vector3d& size, std::size_t count,
                             std::mt19937& random) {
  const double l = size.x(), w = size.y(), h = size.z();
  const double areas[5] = {w * h, w * h, l * h, l * h, l * w};  // front back left right top
  double total = 0.0;
  for (const double area : areas) {
    total += area;
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  ModelCloud cloud;
  for (std::size_t i = 0; i < count; ++i) {
    double pick = unit(random) * total;
    int face = 0;
    while (face < 4 && pick > areas[face]) {
      pick -= areas[face++];
    }
    const double u = unit(random), v = unit(random);
    Eigen::Vector3d p;
    switch (face) {
      case 0: p = {l / 2, (u - 0.5) * w, v * h}; break;
      case 1: p = {-l / 2, (u - 0.5) * w, v * h}; break;
      case 2: p = {(u - 0.5) * l, w / 2, v * h}; break;
      case 3: p = {(u - 0.5) * l, -w / 2, v * h}; break;
      default: p = {(u - 0.5) * l, (v - 0.5) * w, h}; break;
    }
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  }
  return cloud;
}

// `count` points uniformly on a sphere.
inline ModelCloud sphere(const Eigen::Vector3d& centre, double radius, std::size_t count,
                         std::mt19937& random) {
  std::normal_distribution<double> normal(0.0, 1.0);
  ModelCloud cloud;
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Vector3d direction(normal(random), normal(random), normal(random));
    const Eigen::Vector3d p = centre + radius * direction.normalized();
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  }
  return cloud;
}

// A regular grid: x = x0 + i * step for i < nx, and so on.
inline ModelCloud lattice(const Eigen::Vector3d& origin, double step, int nx, int ny, int nz) {
  ModelCloud cloud;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nz; ++k) {
        cloud.push_back(pcl::PointXYZ(static_cast<float>(origin.x() + i * step),
                                      static_cast<float>(origin.y() + j * step),
                                      static_cast<float>(origin.z() + k * step)));
      }
    }
  }
  return cloud;
}

inline ModelCloud shifted(const ModelCloud& cloud, const Eigen::Vector3f& offset) {
  ModelCloud moved = cloud;
  for (pcl::PointXYZ& point : moved.points) {
    point.getVector3fMap() += offset;
  }
  return moved;
}

// The points of a cloud as vectors, to compare clouds point by point.
inline std::vector<Eigen::Vector3f> pointsOf(const ModelCloud& cloud) {
  std::vector<Eigen::Vector3f> points;
  for (const pcl::PointXYZ& point : cloud.points) {
    points.push_back(point.getVector3fMap());
  }
  return points;
}

// A car-sized box: length, width, height in metres.
inline const Eigen::Vector3d kCarSize(4.4, 1.8, 1.5);

}  // namespace testing_clouds
}  // namespace granular
