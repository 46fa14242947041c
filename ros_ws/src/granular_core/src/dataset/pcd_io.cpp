#include "granular_core/dataset/pcd_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>

#include <pcl/io/pcd_io.h>

#include "granular_core/dataset/atomic_file.h"

namespace granular {
namespace {

// Where a scalar field lies in a point record and how it is stored.
struct ScalarField {
  std::size_t offset;
  std::uint8_t datatype;
};

// The first of `names` the file has, as a scalar of any numeric type; nullopt when it has none.
// A field of that name holding several values is an error naming it.
std::optional<ScalarField> scalarField(const pcl::PCLPointCloud2& blob,
                                       std::initializer_list<const char*> names,
                                       const std::filesystem::path& file) {
  for (const char* name : names) {
    for (const pcl::PCLPointField& field : blob.fields) {
      if (field.name != name) {
        continue;
      }
      if (field.count != 1 || field.datatype < pcl::PCLPointField::INT8 ||
          field.datatype > pcl::PCLPointField::FLOAT64) {
        throw std::runtime_error(file.string() + ": PCD field '" + field.name + "' has type " +
                                 std::to_string(field.datatype) + " x" +
                                 std::to_string(field.count) + ", expected one number");
      }
      return ScalarField{field.offset, field.datatype};
    }
  }
  return std::nullopt;
}

template <typename T>
double load(const std::uint8_t* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return static_cast<double>(value);
}

double scalarAt(const std::uint8_t* record, const ScalarField& field) {
  const std::uint8_t* at = record + field.offset;
  switch (field.datatype) {
    case pcl::PCLPointField::INT8: return load<std::int8_t>(at);
    case pcl::PCLPointField::UINT8: return load<std::uint8_t>(at);
    case pcl::PCLPointField::INT16: return load<std::int16_t>(at);
    case pcl::PCLPointField::UINT16: return load<std::uint16_t>(at);
    case pcl::PCLPointField::INT32: return load<std::int32_t>(at);
    case pcl::PCLPointField::UINT32: return load<std::uint32_t>(at);
    case pcl::PCLPointField::FLOAT32: return load<float>(at);
    default: return load<double>(at);
  }
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

  ScalarField xyz[3];
  const char* const names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    const auto field = scalarField(blob, {names[axis]}, file);
    if (!field || (field->datatype != pcl::PCLPointField::FLOAT32 &&
                   field->datatype != pcl::PCLPointField::FLOAT64)) {
      throw std::runtime_error(file.string() + ": PCD has no floating-point '" + names[axis] +
                               "' field; x, y and z are required");
    }
    xyz[axis] = *field;
  }
  // The simulator's uint8 intensity, a Velodyne driver's float32 one, an Ouster's uint16;
  // and the per-point time of each (seconds, float64 or float32).
  const auto intensity = scalarField(blob, {"intensity"}, file);
  const auto timestamp = scalarField(blob, {"timestamp", "time"}, file);

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
      point.x = static_cast<float>(scalarAt(record, xyz[0]));
      point.y = static_cast<float>(scalarAt(record, xyz[1]));
      point.z = static_cast<float>(scalarAt(record, xyz[2]));
      if (intensity) {
        // 0-255 like the simulator's; brighter returns of other sensors saturate.
        const double value = scalarAt(record, *intensity);
        point.intensity = static_cast<std::uint8_t>(
            std::isfinite(value) ? std::clamp(std::round(value), 0.0, 255.0) : 0.0);
      }
      if (timestamp) {
        point.timestamp = scalarAt(record, *timestamp);
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
