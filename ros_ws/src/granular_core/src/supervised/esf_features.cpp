// PCL's ESF estimation, in a translation unit of its own: its templates compile slowly.
#include <cmath>

#include <pcl/features/esf.h>

#include "granular_core/supervised/object_features.h"

namespace granular {

std::vector<float> esfFeatures(const Cloud& object) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr points(new pcl::PointCloud<pcl::PointXYZ>);
  for (const PointXYZIT& point : object.points) {
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      points->push_back(pcl::PointXYZ(point.x, point.y, point.z));
    }
  }
  std::vector<float> features(640, 0.0f);
  if (points->size() < 3) {
    return features;
  }
  pcl::ESFEstimation<pcl::PointXYZ, pcl::ESFSignature640> estimation;
  estimation.setInputCloud(points);
  pcl::PointCloud<pcl::ESFSignature640> signature;
  estimation.compute(signature);
  if (signature.size() == 1) {
    for (std::size_t i = 0; i < features.size(); ++i) {
      const float value = signature[0].histogram[i];
      features[i] = std::isfinite(value) ? value : 0.0f;
    }
  }
  return features;
}

}  // namespace granular
