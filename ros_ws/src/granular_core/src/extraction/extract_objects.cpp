#include "granular_core/extraction/extract_objects.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace granular {

Cloud cropToObjectFrame(const Cloud& cloud, const OrientedBox& box,
                        const Eigen::Vector3d& padding) {
  const Eigen::Isometry3d to_object = box.sensorToObject();
  const Eigen::Vector3d& centre = box.centre();
  const Eigen::Vector3d object_centre(0.0, 0.0, box.size().z() / 2.0);
  const Eigen::Vector3d limit = box.size() / 2.0 + padding;
  // The box's circumscribed sphere rejects most points with a few flops and no rotation.
  const double radius_squared = limit.squaredNorm();

  Cloud object;
  for (const PointXYZIT& point : cloud.points) {
    const Eigen::Vector3d sensor(point.x, point.y, point.z);
    // Written so that NaN and infinite points fail it.
    if (!((sensor - centre).squaredNorm() <= radius_squared)) {
      continue;
    }
    const Eigen::Vector3d local = to_object * sensor;
    if (((local - object_centre).array().abs() <= limit.array()).all()) {
      object.points.emplace_back(static_cast<float>(local.x()), static_cast<float>(local.y()),
                                 static_cast<float>(local.z()), point.intensity, point.timestamp);
    }
  }
  object.width = static_cast<std::uint32_t>(object.points.size());
  object.height = 1;
  object.is_dense = true;
  return object;
}

FrameExtraction extractObjects(const Cloud& cloud, const std::vector<Detection>& detections,
                               const ExtractionConfig& config) {
  FrameExtraction result;
  result.non_finite_points = static_cast<std::size_t>(
      std::count_if(cloud.points.begin(), cloud.points.end(), [](const PointXYZIT& point) {
        return !(std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z));
      }));

  std::unordered_map<std::string, std::size_t> seen_per_label;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& detection = detections[i];
    const std::size_t label_index = ++seen_per_label[detection.label];
    if (!config.labels.empty() && std::find(config.labels.begin(), config.labels.end(),
                                            detection.label) == config.labels.end()) {
      continue;
    }
    const auto reject = [&](const std::string& why) {
      result.errors.push_back("detections[" + std::to_string(i) + "] (id " +
                              std::to_string(detection.id) + ", " + detection.label +
                              "): " + why);
    };
    std::optional<OrientedBox> box;
    try {
      box.emplace(detection.centre, detection.orientation, detection.size);
    } catch (const std::invalid_argument& error) {
      reject(error.what());
      continue;
    }
    if (box->size().maxCoeff() > config.max_box_size) {
      std::ostringstream size;
      size << box->size().x() << " x " << box->size().y() << " x " << box->size().z();
      reject("box of " + size.str() + " m is larger than max_box_size (" +
             std::to_string(config.max_box_size) + " m); skipped as implausible");
      continue;
    }
    Cloud object = cropToObjectFrame(cloud, *box, config.padding);
    result.objects.push_back({detection, *box, label_index, std::move(object)});
  }
  return result;
}

}  // namespace granular
