#include "granular_core/models/model_cloud.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/pcd_io.h"

namespace granular {

ModelCloud toModelCloud(const Cloud& cloud, std::size_t* dropped) {
  ModelCloud model;
  model.reserve(cloud.size());
  for (const PointXYZIT& point : cloud.points) {
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      model.push_back(pcl::PointXYZ(point.x, point.y, point.z));
    }
  }
  if (dropped != nullptr) {
    *dropped = cloud.size() - model.size();
  }
  return model;
}

ModelCloud readModelPcd(const std::filesystem::path& file) { return toModelCloud(readPcd(file)); }

void writeModelPcd(const std::filesystem::path& file, const ModelCloud& cloud) {
  const std::size_t count = cloud.size();
  std::string content = binaryPcdHeader("x y z", "4 4 4", "F F F", "1 1 1", count);
  constexpr std::size_t kRecord = 3 * sizeof(float);
  std::size_t at = content.size();
  content.resize(at + count * kRecord);
  for (const pcl::PointXYZ& point : cloud.points) {
    std::memcpy(&content[at], point.data, kRecord);
    at += kRecord;
  }

  writeFile(file, content, "PCD");
}

}  // namespace granular
