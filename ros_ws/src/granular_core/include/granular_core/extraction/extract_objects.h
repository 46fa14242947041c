#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "granular_core/dataset/detections.h"
#include "granular_core/extraction/extraction_config.h"
#include "granular_core/geometry/oriented_box.h"
#include "granular_core/point_types.h"

namespace granular {

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

/// Extracts every detection of one frame (label filter and padding from `config`; its
/// thresholds are applied when writing, not here). Invalid detections are reported in
/// FrameExtraction::errors and skipped; this never throws for bad box values.
FrameExtraction extractObjects(const Cloud& cloud, const std::vector<Detection>& detections,
                               const ExtractionConfig& config);

}  // namespace granular
