#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "granular_core/config/fields.h"
#include "granular_core/geometry/oriented_box.h"
#include "granular_core/point_types.h"
#include "granular_core/segmentation/occupancy_segmentation.h"

namespace granular {

/// The Background class: segments of a labelled frame that lie on no labelled object (walls,
/// poles, vegetation, clutter), harvested as training objects so that a classifier can say "not
/// a vehicle" to the box-free path's segments (docs/segmentation.md measures the decision).
struct BackgroundConfig {
  std::string label = "Background";  ///< the class name the objects and the decision use
  /// m: a true box grown by this much on each side holds the points that are on an object.
  double margin = 0.3;
  /// A segment with more than this share of its points on objects is no background.
  double max_object_share = 0.1;
  /// A segment with at least this share of its points on one true box (grown by margin) shows
  /// that box's object (labelSegments; extract_objects --segment-objects).
  double min_object_share = 0.5;
  /// deg either side of straight ahead (+x), and m: only segments there are harvested, where
  /// the labels are complete (KITTI labels the camera's view only: 40).
  double half_field_of_view_deg = 180.0;
  double max_range = 80.0;
  /// The decision: a segment the classifier calls `label` with at least this score (the
  /// share of its one-vs-one duels the SVM's answer won, or of kNN's neighbours that voted for
  /// it) is dropped. 1: only when it is unanimous; a vehicle seen badly is often Background
  /// by a plurality only (docs/segmentation.md).
  double min_score = 1.0;
  /// The decision abstains on a segment beyond `abstain_range` m with fewer than
  /// `abstain_points` points: a far car of a few rings and a piece of clutter give the same
  /// point-feature histograms (each point's 20 nearest are the whole object), and such cars
  /// were called Background unanimously. Nearer, a segment that small is a small thing, and the
  /// answer stands (docs/segmentation.md).
  std::size_t abstain_points = 20;
  double abstain_range = 30.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("label", self.label, text("a class name"));
    visit("margin", self.margin, nonNegative("m"));
    visit("max_object_share", self.max_object_share, interval(0, 1, ""));
    visit("min_object_share", self.min_object_share, interval(0, 1, ""));
    visit("half_field_of_view_deg", self.half_field_of_view_deg, interval(0, 180, "deg"));
    visit("max_range", self.max_range, positive("m"));
    visit("min_score", self.min_score, interval(0, 1, ""));
    visit("abstain_points", self.abstain_points, nonNegative("points"));
    visit("abstain_range", self.abstain_range, nonNegative("m"));
  }
};

/// Whether a classifier's answer (`label`, `score`) on a segment of `points` points at
/// `range` m from the sensor drops the segment as background.
inline bool calledBackground(const std::string& label, double score, std::size_t points,
                             double range, const BackgroundConfig& config) {
  const bool abstains = range > config.abstain_range && points < config.abstain_points;
  return !abstains && label == config.label && score >= config.min_score;
}

/// Throws std::invalid_argument naming the field for a value out of range or an empty label.
void validate(const BackgroundConfig& config);

/// A segment of a labelled frame and what it shows: one true box's object, or background.
struct LabelledSegment {
  std::size_t segment = 0;            ///< index into the frame's segments
  std::optional<std::size_t> truth;   ///< index into the true boxes; unset: background
};

/// The segments of `cloud` within the configured view and range, in order, each labelled by
/// the true boxes `truth` (grown by config.margin): background when at most max_object_share
/// of its points lie on any of them, the box holding the most of its points when that box
/// holds at least min_object_share of them; the segments in between are left out.
std::vector<LabelledSegment> labelSegments(const Cloud& cloud,
                                           const std::vector<Segment>& segments,
                                           const std::vector<OrientedBox>& truth,
                                           const BackgroundConfig& config = {});

}  // namespace granular
