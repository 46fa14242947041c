#include "granular_core/segmentation/background.h"

#include <algorithm>
#include <cmath>

namespace granular {

void validate(const BackgroundConfig& config) { config::validateFields(config); }

std::vector<LabelledSegment> labelSegments(const Cloud& cloud,
                                           const std::vector<Segment>& segments,
                                           const std::vector<OrientedBox>& truth,
                                           const BackgroundConfig& config) {
  validate(config);
  // Each true box as the map into its object frame and its half extents grown by the margin.
  std::vector<Eigen::Isometry3d> to_object;
  std::vector<Eigen::Vector3d> half;
  for (const OrientedBox& box : truth) {
    to_object.push_back(box.sensorToObject());
    half.push_back(box.size() / 2.0 + Eigen::Vector3d::Constant(config.margin));
  }
  const auto inBox = [&](std::size_t b, const Eigen::Vector3d& point) {
    Eigen::Vector3d local = to_object[b] * point;
    local.z() -= truth[b].size().z() / 2.0;  // the object frame's origin is on the bottom
    return (local.cwiseAbs().array() <= half[b].array()).all();
  };

  std::vector<LabelledSegment> labelled;
  std::vector<std::size_t> in_box(truth.size());
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Segment& segment = segments[s];
    const Eigen::Vector3d& centre = segment.box.centre();
    const double azimuth_deg = std::abs(std::atan2(centre.y(), centre.x())) * 180.0 / M_PI;
    if (segment.indices.empty() || azimuth_deg > config.half_field_of_view_deg ||
        centre.head<2>().norm() > config.max_range) {
      continue;
    }
    std::fill(in_box.begin(), in_box.end(), 0);
    std::size_t on_objects = 0;
    for (const std::size_t i : segment.indices) {
      const Eigen::Vector3d point = cloud[i].getVector3fMap().cast<double>();
      bool on_an_object = false;
      for (std::size_t b = 0; b < truth.size(); ++b) {
        if (inBox(b, point)) {
          ++in_box[b];
          on_an_object = true;
        }
      }
      on_objects += on_an_object;
    }
    const double points = static_cast<double>(segment.indices.size());
    if (static_cast<double>(on_objects) <= config.max_object_share * points) {
      labelled.push_back({s, std::nullopt});
      continue;
    }
    const std::size_t most =
        static_cast<std::size_t>(std::max_element(in_box.begin(), in_box.end()) - in_box.begin());
    if (static_cast<double>(in_box[most]) >= config.min_object_share * points) {
      labelled.push_back({s, most});
    }
  }
  return labelled;
}

}  // namespace granular
