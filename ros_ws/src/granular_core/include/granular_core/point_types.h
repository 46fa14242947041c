#pragma once

#include <cstdint>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace granular {

/// One LiDAR return as the bag-to-files tool writes it: position in metres, 8-bit intensity and
/// the return's time in seconds. Its PCD fields are `x y z intensity timestamp`, SIZE 4 4 4 1 8,
/// TYPE F F F U F; pcl::PointXYZI would read the uint8 intensity as float and lose it.
struct EIGEN_ALIGN16 PointXYZIT {
  PCL_ADD_POINT4D;
  std::uint8_t intensity;
  double timestamp;

  PointXYZIT() : PointXYZIT(0.0f, 0.0f, 0.0f, 0, 0.0) {}
  PointXYZIT(float x_in, float y_in, float z_in, std::uint8_t intensity_in, double timestamp_in)
      : intensity(intensity_in), timestamp(timestamp_in) {
    x = x_in;
    y = y_in;
    z = z_in;
    data[3] = 1.0f;
  }
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

/// A cloud of PointXYZIT, the type every granular stage reads and writes.
using Cloud = pcl::PointCloud<PointXYZIT>;

/// Class models are geometry only: intensity and stamps of points stacked from hundreds of
/// scans mean nothing once averaged in a voxel, and PCL's filters and registration are
/// precompiled for pcl::PointXYZ.
using ModelCloud = pcl::PointCloud<pcl::PointXYZ>;

}  // namespace granular

POINT_CLOUD_REGISTER_POINT_STRUCT(granular::PointXYZIT,
                                  (float, x, x)
                                  (float, y, y)
                                  (float, z, z)
                                  (std::uint8_t, intensity, intensity)
                                  (double, timestamp, timestamp))
