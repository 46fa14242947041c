#pragma once

#include <cstddef>
#include <filesystem>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "granular_core/point_types.h"

namespace granular {

/// Class models are geometry only: intensity and stamps of points stacked from hundreds of
/// scans mean nothing once averaged in a voxel, and PCL's filters and registration are
/// precompiled for pcl::PointXYZ.
using ModelCloud = pcl::PointCloud<pcl::PointXYZ>;

/// The finite points of `cloud`, x y z only; `dropped`, when given, receives how many were not
/// finite.
ModelCloud toModelCloud(const Cloud& cloud, std::size_t* dropped = nullptr);

/// Reads any PCD with float x, y and z fields (granular::readPcd) as a model cloud, without
/// its non-finite points. Throws std::runtime_error naming the file.
ModelCloud readModelPcd(const std::filesystem::path& file);

/// Writes `cloud` as binary PCD with the fields `x y z`, checking every write (writeFile), for
/// a staging folder. Throws std::runtime_error naming the file on failure.
void writeModelPcd(const std::filesystem::path& file, const ModelCloud& cloud);

}  // namespace granular
