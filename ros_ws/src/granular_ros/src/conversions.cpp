#include "granular_ros/conversions.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace granular_ros {

namespace {

// The field called `name`, or nullptr.
const sensor_msgs::PointField* findField(const sensor_msgs::PointCloud2& message,
                                         const std::string& name) {
  for (const sensor_msgs::PointField& field : message.fields) {
    if (field.name == name) {
      return &field;
    }
  }
  return nullptr;
}

template <typename T>
T read(const std::uint8_t* point, std::uint32_t offset) {
  T value;
  std::memcpy(&value, point + offset, sizeof(T));
  return value;
}

// A field's value as a double, whatever its numeric type.
double readAny(const std::uint8_t* point, const sensor_msgs::PointField& field) {
  switch (field.datatype) {
    case sensor_msgs::PointField::INT8:
      return read<std::int8_t>(point, field.offset);
    case sensor_msgs::PointField::UINT8:
      return read<std::uint8_t>(point, field.offset);
    case sensor_msgs::PointField::INT16:
      return read<std::int16_t>(point, field.offset);
    case sensor_msgs::PointField::UINT16:
      return read<std::uint16_t>(point, field.offset);
    case sensor_msgs::PointField::INT32:
      return read<std::int32_t>(point, field.offset);
    case sensor_msgs::PointField::UINT32:
      return read<std::uint32_t>(point, field.offset);
    case sensor_msgs::PointField::FLOAT32:
      return read<float>(point, field.offset);
    case sensor_msgs::PointField::FLOAT64:
      return read<double>(point, field.offset);
    default:
      return 0.0;
  }
}

}  // namespace

granular::Cloud toCloud(const sensor_msgs::PointCloud2& message) {
  const char* const axes[3] = {"x", "y", "z"};
  const sensor_msgs::PointField* xyz[3];
  for (int axis = 0; axis < 3; ++axis) {
    xyz[axis] = findField(message, axes[axis]);
    if (xyz[axis] == nullptr || xyz[axis]->datatype != sensor_msgs::PointField::FLOAT32) {
      throw std::runtime_error(std::string("the cloud has no float32 field '") + axes[axis] + "'");
    }
  }
  const sensor_msgs::PointField* intensity = findField(message, "intensity");
  const sensor_msgs::PointField* timestamp = findField(message, "timestamp");
  const std::size_t count = static_cast<std::size_t>(message.width) * message.height;
  if (message.data.size() < count * message.point_step) {
    throw std::runtime_error("the cloud's data is shorter than width x height x point_step");
  }
  granular::Cloud cloud;
  cloud.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* point = &message.data[i * message.point_step];
    // Intensity as the simulator gives it, 0-255; a float intensity is clamped into that.
    const double level = intensity ? std::clamp(readAny(point, *intensity), 0.0, 255.0) : 0.0;
    cloud.push_back(granular::PointXYZIT(
        read<float>(point, xyz[0]->offset), read<float>(point, xyz[1]->offset),
        read<float>(point, xyz[2]->offset), static_cast<std::uint8_t>(std::lround(level)),
        timestamp ? readAny(point, *timestamp) : 0.0));
  }
  return cloud;
}

std::vector<granular::Detection> toDetections(const lgsvl_msgs::Detection3DArray& message) {
  std::vector<granular::Detection> detections;
  detections.reserve(message.detections.size());
  for (const lgsvl_msgs::Detection3D& in : message.detections) {
    granular::Detection detection;
    detection.id = in.id;
    detection.label = in.label;
    const auto& pose = in.bbox.position;
    detection.centre = {pose.position.x, pose.position.y, pose.position.z};
    detection.orientation = Eigen::Quaterniond(pose.orientation.w, pose.orientation.x,
                                               pose.orientation.y, pose.orientation.z);
    detection.size = {in.bbox.size.x, in.bbox.size.y, in.bbox.size.z};
    detections.push_back(detection);
  }
  return detections;
}

lgsvl_msgs::Detection3D toMessage(const granular::OrientedBox& box, const std::string& label,
                                  std::uint32_t id, float score) {
  lgsvl_msgs::Detection3D detection;
  detection.id = id;
  detection.label = label;
  detection.score = score;
  auto& pose = detection.bbox.position;
  pose.position.x = box.centre().x();
  pose.position.y = box.centre().y();
  pose.position.z = box.centre().z();
  pose.orientation.w = box.orientation().w();
  pose.orientation.x = box.orientation().x();
  pose.orientation.y = box.orientation().y();
  pose.orientation.z = box.orientation().z();
  detection.bbox.size.x = box.size().x();
  detection.bbox.size.y = box.size().y();
  detection.bbox.size.z = box.size().z();
  return detection;
}

}  // namespace granular_ros
