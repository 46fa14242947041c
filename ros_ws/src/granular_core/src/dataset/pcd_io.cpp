#include "granular_core/dataset/pcd_io.h"

#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>

#include <pcl/io/pcd_io.h>

#include "granular_core/dataset/atomic_file.h"

namespace granular {
namespace {

// Byte offset of field `name` in a point record, checked against the type PointXYZIT uses;
// nullopt when the file has no such field.
std::optional<std::size_t> fieldOffset(const pcl::PCLPointCloud2& blob, const std::string& name,
                                       std::uint8_t datatype, const std::filesystem::path& file) {
  for (const pcl::PCLPointField& field : blob.fields) {
    if (field.name != name) {
      continue;
    }
    if (field.datatype != datatype || field.count != 1) {
      throw std::runtime_error(file.string() + ": PCD field '" + name + "' has type " +
                               std::to_string(field.datatype) + " x" +
                               std::to_string(field.count) + ", expected type " +
                               std::to_string(datatype) + " x1");
    }
    return field.offset;
  }
  return std::nullopt;
}

}  // namespace

Cloud readPcd(const std::filesystem::path& file) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw std::runtime_error(file.string() + ": no such PCD file");
  }
  pcl::PCLPointCloud2 blob;
  pcl::PCDReader reader;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0;
  int data_type = 0;
  unsigned int data_index = 0;
  // PCL 1.13's read() crashes on a file without a PCD header, so the header is checked first.
  if (reader.readHeader(file.string(), blob, origin, orientation, version, data_type,
                        data_index) < 0 ||
      blob.fields.empty()) {
    throw std::runtime_error(file.string() + ": not a PCD file (no FIELDS in its header)");
  }
  if (reader.read(file.string(), blob) < 0) {
    throw std::runtime_error(file.string() + ": cannot read the PCD data");
  }

  std::size_t xyz[3];
  const char* const names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    const auto offset = fieldOffset(blob, names[axis], pcl::PCLPointField::FLOAT32, file);
    if (!offset) {
      throw std::runtime_error(file.string() + ": PCD has no '" + names[axis] +
                               "' field; x, y and z are required");
    }
    xyz[axis] = *offset;
  }
  const auto intensity = fieldOffset(blob, "intensity", pcl::PCLPointField::UINT8, file);
  const auto timestamp = fieldOffset(blob, "timestamp", pcl::PCLPointField::FLOAT64, file);

  if (blob.data.size() < static_cast<std::size_t>(blob.row_step) * blob.height) {
    throw std::runtime_error(file.string() + ": PCD data is shorter than its header says");
  }

  Cloud cloud;
  cloud.resize(static_cast<std::size_t>(blob.width) * blob.height);
  std::size_t index = 0;
  for (std::uint32_t row = 0; row < blob.height; ++row) {
    const std::uint8_t* record = blob.data.data() + static_cast<std::size_t>(row) * blob.row_step;
    for (std::uint32_t column = 0; column < blob.width; ++column, record += blob.point_step) {
      PointXYZIT& point = cloud.points[index++];
      std::memcpy(&point.x, record + xyz[0], sizeof(float));
      std::memcpy(&point.y, record + xyz[1], sizeof(float));
      std::memcpy(&point.z, record + xyz[2], sizeof(float));
      if (intensity) {
        point.intensity = record[*intensity];
      }
      if (timestamp) {
        std::memcpy(&point.timestamp, record + *timestamp, sizeof(double));
      }
    }
  }
  cloud.is_dense = blob.is_dense;
  return cloud;
}

std::string binaryPcdHeader(const std::string& fields, const std::string& sizes,
                            const std::string& types, const std::string& counts,
                            std::size_t points) {
  return "# .PCD v0.7 - Point Cloud Data file format\n"
         "VERSION 0.7\n"
         "FIELDS " + fields + "\n"
         "SIZE " + sizes + "\n"
         "TYPE " + types + "\n"
         "COUNT " + counts + "\n"
         "WIDTH " + std::to_string(points) + "\n"
         "HEIGHT 1\n"
         "VIEWPOINT 0 0 0 1 0 0 0\n"
         "POINTS " + std::to_string(points) + "\n"
         "DATA binary\n";
}

void writePcdBinary(const std::filesystem::path& file, const Cloud& cloud) {
  // Written by hand rather than with pcl::PCDWriter, which maps, locks and chmods every file:
  // with thousands of small object files those system calls took most of the stage's time.
  const std::size_t count = cloud.size();
  std::string content =
      binaryPcdHeader("x y z intensity timestamp", "4 4 4 1 8", "F F F U F", "1 1 1 1 1", count);
  constexpr std::size_t kRecord = 3 * sizeof(float) + sizeof(std::uint8_t) + sizeof(double);
  std::size_t at = content.size();
  content.resize(at + count * kRecord);
  for (const PointXYZIT& point : cloud.points) {
    std::memcpy(&content[at], point.data, 3 * sizeof(float));
    content[at + 3 * sizeof(float)] = static_cast<char>(point.intensity);
    std::memcpy(&content[at + 3 * sizeof(float) + 1], &point.timestamp, sizeof(double));
    at += kRecord;
  }

  writeFile(file, content, "PCD");
}

}  // namespace granular
