#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "granular_core/dataset/detections.h"
#include "granular_core/extraction/extraction_config.h"
#include "granular_core/geometry/oriented_box.h"
#include "granular_core/point_types.h"

namespace granular {

/// "detections[<index>] (id <id>, <label>)": how every message names a detection of a frame.
std::string detectionName(const Detection& detection, std::size_t index);

/// The box of `detection`, the frame's `index`-th; nullopt when its numbers make none (a size
/// not positive, a number not finite, no rotation: OrientedBox's checks), and `problem` then
/// says so, the detection named ("detections[2] (id 7, Car): size must be positive ...").
std::optional<OrientedBox> detectionBox(const Detection& detection, std::size_t index,
                                        std::string& problem);

/// detectionBox, and nullopt too for a box longer, wider or higher than `max_box_size` m
/// (ExtractionConfig's bound on plausible boxes), `problem` then giving its size
/// ("detections[2] (id 7, Car): box of 1e+30 x 2 x 1.5 m is larger than max_box_size (30 m):
/// implausible").
std::optional<OrientedBox> plausibleDetectionBox(const Detection& detection, std::size_t index,
                                                 double max_box_size, std::string& problem);

/// `detection` turned half a turn about its z axis where its x axis points towards the sensor
/// (the origin), unchanged where it points away: a box-free cuboid's heading is known modulo
/// 180 degrees only, and label_box_free turns the training objects by this rule, so that a
/// classifier learnt from them sees every object from the same side of its frame.
Detection facingAwayFromSensor(Detection detection);

/// The points of one detection, moved into its object frame.
struct ExtractedObject {
  Detection detection;
  OrientedBox box;
  /// 1-based position of the detection among the frame's detections with the same label
  /// (counted over all of them, so it does not depend on the label filter or on validity).
  std::size_t label_index;
  /// Points inside the padded box, in the object frame (see OrientedBox), intensity and
  /// timestamp kept.
  Cloud cloud;
};

/// What extracting one frame gave.
struct FrameExtraction {
  /// One per valid detection whose label passes the filter, in input order; may be empty clouds.
  std::vector<ExtractedObject> objects;
  /// One message per rejected detection, naming its index, id, label and the reason.
  std::vector<std::string> errors;
  /// Points of the input cloud with a NaN or infinite coordinate; they are never extracted.
  std::size_t non_finite_points = 0;
};

/// Points of `cloud` inside `box` grown by `padding` on each side (box axes, metres; the
/// boundary counts as inside), mapped into the box's object frame. Non-finite points are skipped.
Cloud cropToObjectFrame(const Cloud& cloud, const OrientedBox& box,
                        const Eigen::Vector3d& padding);

/// One frame's points bucketed by their x-y cell, for cropping many boxes out of it: a box
/// then tests only the points of the cells under it instead of the whole cloud (a KITTI frame
/// of 120,000 points with 200 boxes: 24 million point tests become about 200 times the
/// points near a box). crop() gives what cropToObjectFrame gives, the same points in the same
/// order. The cloud must outlive the cropper and stay unchanged.
class FrameCropper {
 public:
  /// Buckets `cloud`'s finite points into square cells of `cell_size` metres (larger where
  /// the points spread so far that the grid would exceed about four million cells).
  explicit FrameCropper(const Cloud& cloud, double cell_size = 1.0);

  /// cropToObjectFrame(cloud, box, padding), looking only at the cells under the box.
  Cloud crop(const OrientedBox& box, const Eigen::Vector3d& padding) const;

 private:
  const Cloud& cloud_;
  double cell_size_ = 1.0;
  double min_x_ = 0.0, min_y_ = 0.0;
  std::size_t columns_ = 0, rows_ = 0;
  /// Point indices by cell (row after row), ascending within a cell; cell c holds
  /// by_cell_[start_[c]] up to by_cell_[start_[c + 1]].
  std::vector<std::uint32_t> by_cell_;
  std::vector<std::uint32_t> start_;
};

/// Extracts every detection of one frame (label filter and padding from `config`; its
/// thresholds are applied when writing, not here). Invalid detections are reported in
/// FrameExtraction::errors and skipped; this never throws for bad box values.
FrameExtraction extractObjects(const Cloud& cloud, const std::vector<Detection>& detections,
                               const ExtractionConfig& config);

}  // namespace granular
