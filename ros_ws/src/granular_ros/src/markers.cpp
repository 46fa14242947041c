#include "granular_ros/markers.h"

#include <array>
#include <cstdio>
#include <map>

namespace granular_ros {
namespace {

using Colour = std::array<float, 3>;

// The palette of granular_tools/visualization/detection_markers.py, so both views agree.
const std::map<std::string, Colour>& palette() {
  static const std::map<std::string, Colour> colours = {
      {"Sedan", {0.2f, 0.6f, 1.0f}},      {"SUV", {0.3f, 0.9f, 0.3f}},
      {"Hatchback", {1.0f, 0.6f, 0.1f}},  {"Jeep", {1.0f, 0.25f, 0.25f}},
      {"BoxTruck", {0.75f, 0.45f, 1.0f}}, {"SchoolBus", {1.0f, 0.95f, 0.2f}},
      {"Pedestrian", {0.2f, 1.0f, 1.0f}}};
  return colours;
}

std_msgs::ColorRGBA colour(const Colour& rgb) {
  std_msgs::ColorRGBA value;
  value.r = rgb[0];
  value.g = rgb[1];
  value.b = rgb[2];
  value.a = 1.0f;
  return value;
}

std_msgs::ColorRGBA colourOf(const std::string& label) {
  const auto found = palette().find(label);
  return colour(found == palette().end() ? Colour{0.8f, 0.8f, 0.8f} : found->second);
}

geometry_msgs::Point point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

}  // namespace

visualization_msgs::MarkerArray predictionMarkers(const lgsvl_msgs::Detection3DArray& predicted,
                                                  const std::vector<std::string>& truth,
                                                  double lifetime, bool tracks) {
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.header = predicted.header;
  clear.ns = "predictions";
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  for (std::size_t i = 0; i < predicted.detections.size(); ++i) {
    const lgsvl_msgs::Detection3D& detection = predicted.detections[i];
    const std::string& label = detection.label;
    const std::string true_label = i < truth.size() ? truth[i] : "";
    // An object too small to classify ("unknown") is not a wrong prediction.
    const bool wrong = !true_label.empty() && label != "unknown" && true_label != label;
    const auto& size = detection.bbox.size;

    visualization_msgs::Marker outline;
    outline.header = predicted.header;
    outline.ns = "predictions";
    outline.id = static_cast<int>(2 * i);
    outline.type = visualization_msgs::Marker::LINE_LIST;
    outline.action = visualization_msgs::Marker::ADD;
    outline.pose = detection.bbox.position;
    outline.scale.x = wrong ? 0.15 : 0.06;
    outline.color = colourOf(label);
    outline.lifetime = ros::Duration(lifetime);
    const double half[3] = {size.x / 2, size.y / 2, size.z / 2};
    for (int a = 0; a < 8; ++a) {
      for (int b = a + 1; b < 8; ++b) {
        const int differ = a ^ b;
        if (differ == 1 || differ == 2 || differ == 4) {  // corners one axis apart: an edge
          for (const int corner : {a, b}) {
            outline.points.push_back(point((corner & 1 ? 1 : -1) * half[0],
                                           (corner & 2 ? 1 : -1) * half[1],
                                           (corner & 4 ? 1 : -1) * half[2]));
          }
        }
      }
    }

    visualization_msgs::Marker tag;
    tag.header = predicted.header;
    tag.ns = "predictions";
    tag.id = static_cast<int>(2 * i + 1);
    tag.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    tag.action = visualization_msgs::Marker::ADD;
    tag.pose.position = detection.bbox.position.position;
    tag.pose.position.z += half[2] + 0.5;
    tag.pose.orientation.w = 1.0;
    tag.scale.z = 0.7;
    tag.lifetime = ros::Duration(lifetime);
    char text[160];
    char track[24] = "";
    if (tracks) {
      std::snprintf(track, sizeof(track), "#%u ", detection.id);
    }
    if (wrong) {
      std::snprintf(text, sizeof(text), "%sX %s (true: %s)", track, label.c_str(),
                    true_label.c_str());
      tag.color = colour({1.0f, 0.1f, 0.1f});
    } else if (label == "unknown") {
      std::snprintf(text, sizeof(text), "%stoo few points%s%s", track,
                    true_label.empty() ? "" : ": ", true_label.c_str());
      tag.color = colourOf(label);
      tag.scale.z = 0.4;
    } else {
      std::snprintf(text, sizeof(text), "%s%s%s %.2f", track, label.c_str(),
                    true_label.empty() ? "" : " ok", detection.score);
      tag.color = colourOf(label);
    }
    tag.text = text;
    markers.markers.push_back(outline);
    markers.markers.push_back(tag);
    if (tracks) {
      visualization_msgs::Marker arrow;
      arrow.header = predicted.header;
      arrow.ns = "velocities";
      arrow.id = static_cast<int>(i);
      arrow.type = visualization_msgs::Marker::ARROW;
      arrow.action = visualization_msgs::Marker::ADD;
      arrow.pose.orientation.w = 1.0;
      const auto& centre = detection.bbox.position.position;
      const auto& velocity = detection.velocity.linear;
      const double top = centre.z + half[2];
      arrow.points = {point(centre.x, centre.y, top),
                      point(centre.x + velocity.x, centre.y + velocity.y, top)};
      arrow.scale.x = 0.15;  // shaft diameter, m
      arrow.scale.y = 0.4;   // head diameter, m
      arrow.scale.z = 0.6;   // head length, m
      arrow.color = colourOf(label);
      arrow.lifetime = ros::Duration(lifetime);
      markers.markers.push_back(arrow);
    }
  }
  return markers;
}

}  // namespace granular_ros
