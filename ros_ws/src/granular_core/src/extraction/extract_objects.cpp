#include "granular_core/extraction/extract_objects.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <pcl/common/point_tests.h>

namespace granular {

namespace {

// A box's crop test, shared by the whole-cloud scan and the cropper so that both keep the
// same points.
class BoxTest {
 public:
  BoxTest(const OrientedBox& box, const Eigen::Vector3d& padding)
      : to_object_(box.sensorToObject()),
        centre_(box.centre()),
        object_centre_(0.0, 0.0, box.size().z() / 2.0),
        limit_(box.size() / 2.0 + padding),
        // The box's circumscribed sphere rejects most points with a few flops, no rotation.
        radius_squared_(limit_.squaredNorm()) {}

  const Eigen::Vector3d& centre() const { return centre_; }
  // Half the x and y extents of the padded box in the sensor frame, around centre(): its
  // corners seen from above lie within them.
  Eigen::Vector2d halfExtentXY() const {
    // Row i of the object-to-sensor rotation is column i of to_object_'s.
    const Eigen::Matrix3d& rotation = to_object_.linear();
    return {rotation.col(0).cwiseAbs().dot(limit_), rotation.col(1).cwiseAbs().dot(limit_)};
  }

  // `point` in the object frame when it lies in the padded box.
  std::optional<Eigen::Vector3d> inside(const PointXYZIT& point) const {
    const Eigen::Vector3d sensor(point.x, point.y, point.z);
    // Written so that NaN and infinite points fail it.
    if (!((sensor - centre_).squaredNorm() <= radius_squared_)) {
      return std::nullopt;
    }
    const Eigen::Vector3d local = toObject(point);
    if (((local - object_centre_).array().abs() <= limit_.array()).all()) {
      return local;
    }
    return std::nullopt;
  }

  // `point` in the object frame, as inside() computes it.
  Eigen::Vector3d toObject(const PointXYZIT& point) const {
    return to_object_ * Eigen::Vector3d(point.x, point.y, point.z);
  }

 private:
  Eigen::Isometry3d to_object_;
  Eigen::Vector3d centre_;
  Eigen::Vector3d object_centre_;
  Eigen::Vector3d limit_;
  double radius_squared_;
};

// Appends `point` at its object-frame position `local`, intensity and timestamp kept.
void append(const PointXYZIT& point, const Eigen::Vector3d& local, Cloud& object) {
  object.points.emplace_back(static_cast<float>(local.x()), static_cast<float>(local.y()),
                             static_cast<float>(local.z()), point.intensity, point.timestamp);
}

void finishCloud(Cloud& object) {
  object.width = static_cast<std::uint32_t>(object.points.size());
  object.height = 1;
  object.is_dense = true;
}

// Puts distinct point indices in ascending order. A box's points come cell by cell, and a
// scan's cloud holds them ring after ring, so they spread over most of the cloud's indices:
// where a bit per index in their range costs less than sorting them, the bits order them.
// (Sorting was a quarter of a crowded demo frame's crop instructions, two fifths of a KITTI
// frame's, where a car near the sensor keeps thousands of points.)
void inCloudOrder(std::vector<std::uint32_t>& indices) {
  if (indices.size() < 2) {
    return;
  }
  const auto [low, high] = std::minmax_element(indices.begin(), indices.end());
  const std::uint32_t first = *low;
  const std::size_t words = (*high - first) / 64 + 1;
  if (words > 4 * indices.size()) {
    std::sort(indices.begin(), indices.end());
    return;
  }
  std::vector<std::uint64_t> bits(words, 0);
  for (const std::uint32_t index : indices) {
    bits[(index - first) / 64] |= std::uint64_t{1} << ((index - first) % 64);
  }
  indices.clear();
  for (std::size_t word = 0; word < words; ++word) {
    for (std::uint64_t set = bits[word]; set != 0; set &= set - 1) {
      indices.push_back(first + static_cast<std::uint32_t>(word * 64 + __builtin_ctzll(set)));
    }
  }
}

// The grid's cells at most, whatever the points' spread (4 million: 16 MB of cell starts).
constexpr double kMaxCells = 4.0e6;

}  // namespace

Cloud cropToObjectFrame(const Cloud& cloud, const OrientedBox& box,
                        const Eigen::Vector3d& padding) {
  const BoxTest test(box, padding);
  Cloud object;
  for (const PointXYZIT& point : cloud.points) {
    if (const std::optional<Eigen::Vector3d> local = test.inside(point)) {
      append(point, *local, object);
    }
  }
  finishCloud(object);
  return object;
}

FrameCropper::FrameCropper(const Cloud& cloud, double cell_size) : cloud_(cloud) {
  if (!(cell_size > 0.0) || !std::isfinite(cell_size)) {
    throw std::invalid_argument("FrameCropper: cell_size must be a positive number of metres");
  }
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x;
  min_x_ = std::numeric_limits<double>::infinity();
  min_y_ = min_x_;
  for (const PointXYZIT& point : cloud.points) {
    if (pcl::isFinite(point)) {
      min_x_ = std::min(min_x_, double(point.x));
      max_x = std::max(max_x, double(point.x));
      min_y_ = std::min(min_y_, double(point.y));
      max_y = std::max(max_y, double(point.y));
    }
  }
  if (!(min_x_ <= max_x)) {  // no finite point
    start_.assign(1, 0);
    return;
  }
  const double spread = std::max(max_x - min_x_, max_y - min_y_);
  cell_size_ = std::max(cell_size, spread / std::sqrt(kMaxCells));
  columns_ = static_cast<std::size_t>((max_x - min_x_) / cell_size_) + 1;
  rows_ = static_cast<std::size_t>((max_y - min_y_) / cell_size_) + 1;
  // A counting sort of the point indices by cell keeps each cell's points in cloud order.
  std::vector<std::uint32_t> cell_of(cloud.size());
  start_.assign(columns_ * rows_ + 1, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointXYZIT& point = cloud.points[i];
    if (!pcl::isFinite(point)) {
      cell_of[i] = static_cast<std::uint32_t>(columns_ * rows_);  // in no cell
      continue;
    }
    const auto column = std::min(columns_ - 1, static_cast<std::size_t>((point.x - min_x_) / cell_size_));
    const auto row = std::min(rows_ - 1, static_cast<std::size_t>((point.y - min_y_) / cell_size_));
    cell_of[i] = static_cast<std::uint32_t>(row * columns_ + column);
    ++start_[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < columns_ * rows_; ++c) {
    start_[c + 1] += start_[c];
  }
  by_cell_.resize(start_.back());
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cell_of[i] < columns_ * rows_) {
      by_cell_[next[cell_of[i]]++] = static_cast<std::uint32_t>(i);
    }
  }
}

Cloud FrameCropper::crop(const OrientedBox& box, const Eigen::Vector3d& padding) const {
  const BoxTest test(box, padding);
  Cloud object;
  // The box's x-y bounds, a hair wider than the exact test, whose rounding could pass a point
  // a last bit farther: within its circumscribed circle's square, a third of it for a car
  // along an axis.
  const Eigen::Vector2d half =
      test.halfExtentXY() * (1.0 + 1e-9) + Eigen::Vector2d::Constant(1e-9);
  const Eigen::Vector3d& centre = test.centre();
  // The cells under those bounds, clamped to the grid.
  const auto cellRange = [this](double low, double high, double origin, std::size_t count) {
    const double first = std::floor((low - origin) / cell_size_);
    const double last = std::floor((high - origin) / cell_size_);
    return std::pair<std::size_t, std::size_t>(
        static_cast<std::size_t>(std::clamp(first, 0.0, double(count))),
        static_cast<std::size_t>(std::clamp(last + 1.0, 0.0, double(count))));
  };
  if (columns_ == 0 || !half.allFinite() || !centre.allFinite()) {
    finishCloud(object);
    return object;
  }
  const auto [first_column, end_column] =
      cellRange(centre.x() - half.x(), centre.x() + half.x(), min_x_, columns_);
  const auto [first_row, end_row] =
      cellRange(centre.y() - half.y(), centre.y() + half.y(), min_y_, rows_);
  std::vector<std::uint32_t> kept;  // point indices
  if (first_column < end_column) {
    for (std::size_t row = first_row; row < end_row; ++row) {
      const std::size_t cells = row * columns_;
      for (std::uint32_t c = start_[cells + first_column]; c < start_[cells + end_column]; ++c) {
        if (test.inside(cloud_.points[by_cell_[c]])) {
          kept.push_back(by_cell_[c]);
        }
      }
    }
  }
  // Cloud order, as the whole-cloud scan keeps them; the kept points are transformed again
  // below (the same arithmetic, the same values) rather than carried through the ordering.
  inCloudOrder(kept);
  object.points.reserve(kept.size());
  for (const std::uint32_t index : kept) {
    append(cloud_.points[index], test.toObject(cloud_.points[index]), object);
  }
  finishCloud(object);
  return object;
}

Detection facingAwayFromSensor(Detection detection) {
  const Eigen::Vector3d axis = detection.orientation * Eigen::Vector3d::UnitX();
  if (axis.head<2>().dot(detection.centre.head<2>()) < 0.0) {
    const Eigen::Quaterniond half_turn(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
    detection.orientation = detection.orientation * half_turn;
  }
  return detection;
}

std::string detectionName(const Detection& detection, std::size_t index) {
  return "detections[" + std::to_string(index) + "] (id " + std::to_string(detection.id) + ", " +
         detection.label + ")";
}

std::optional<OrientedBox> detectionBox(const Detection& detection, std::size_t index,
                                        std::string& problem) {
  try {
    return OrientedBox(detection.centre, detection.orientation, detection.size);
  } catch (const std::invalid_argument& error) {
    problem = detectionName(detection, index) + ": " + error.what();
    return std::nullopt;
  }
}

std::optional<OrientedBox> plausibleDetectionBox(const Detection& detection, std::size_t index,
                                                 double max_box_size, std::string& problem) {
  std::optional<OrientedBox> box = detectionBox(detection, index, problem);
  if (box && box->size().maxCoeff() > max_box_size) {
    std::ostringstream message;
    message << detectionName(detection, index) << ": box of " << box->size().x() << " x "
            << box->size().y() << " x " << box->size().z() << " m is larger than max_box_size ("
            << max_box_size << " m): implausible";
    problem = message.str();
    return std::nullopt;
  }
  return box;
}

FrameExtraction extractObjects(const Cloud& cloud, const std::vector<Detection>& detections,
                               const ExtractionConfig& config) {
  FrameExtraction result;
  result.non_finite_points = static_cast<std::size_t>(
      std::count_if(cloud.points.begin(), cloud.points.end(), [](const PointXYZIT& point) {
        return !pcl::isFinite(point);
      }));

  // Bucketing the points costs about one pass over them: worth it from two boxes on.
  std::optional<FrameCropper> cropper;
  if (detections.size() >= 2) {
    cropper.emplace(cloud);
  }
  std::unordered_map<std::string, std::size_t> seen_per_label;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& detection = detections[i];
    const std::size_t label_index = ++seen_per_label[detection.label];
    if (!config.labels.empty() && std::find(config.labels.begin(), config.labels.end(),
                                            detection.label) == config.labels.end()) {
      continue;
    }
    std::string problem;
    const std::optional<OrientedBox> box =
        plausibleDetectionBox(detection, i, config.max_box_size, problem);
    if (!box) {
      result.errors.push_back(problem);
      continue;
    }
    Cloud object = cropper ? cropper->crop(*box, config.padding)
                           : cropToObjectFrame(cloud, *box, config.padding);
    result.objects.push_back({detection, *box, label_index, std::move(object)});
  }
  return result;
}

}  // namespace granular
