#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/dataset/output_folder.h"
#include "granular_core/segmentation/object_segmentation.h"
#include "granular_core/supervised/supervised_classifier.h"

namespace granular {

/// Which true objects and segments an evaluation counts.
struct SegmentationEvaluationOptions {
  double max_distance = 1.0;   ///< m: a segment's box centre this near a true centre finds it
  std::size_t min_points = 10; ///< points a true box must hold to count as visible
  /// deg: only objects and segments within this of straight ahead (+x) count, e.g. the
  /// camera's view of camera-labelled data (KITTI's); 180: all around.
  double half_field_of_view_deg = 180.0;
  double max_range = 1e9;      ///< m: only objects and segments nearer than this count
  /// The Background decision: a classifier (train_classifier's, trained with Background
  /// objects) whose label for a segment's points drops the segment when it is the segmentation
  /// config's background.label; null: no decision.
  const SupervisedClassifier* classifier = nullptr;
  /// Boxes from a cuboid fitter: each segment's box becomes the cuboid `cuboids` fits to it
  /// (with the frame's free space as `free_space` says), when it fits one; the recall then
  /// measures the whole box-free chain. Null: the segments' own boxes.
  const CuboidFitter* cuboids = nullptr;
  FreeSpaceConfig free_space;
  /// Whether a cloud whose road is not where the sensor's frame puts it (checkGround) is only
  /// named among the frames without ground; otherwise it stops the evaluation (an error naming
  /// the frame and the remedies; nothing saved).
  bool allow_other_frames = false;
  /// A folder to write what the segmentation saw into, for pictures and inspection (empty:
  /// none): per frame `<stamp>.json`, the segments' boxes (or cuboids) as detections (label
  /// `unknown`, or the classifier's), and `<stamp>.pcd`, the cloud's x y z with each point's `height` above the
  /// ground and its `segment` (-1 ground, 0 in no segment, k + 1 in segment k). An
  /// OutputFolder: built beside itself and put in place when complete.
  std::filesystem::path save;
  OutputPolicy save_policy;
  /// Called with (frames done, frames) after each frame; may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// A segmentation method's figures over a frames folder.
struct SegmentationEvaluation {
  std::size_t frames = 0;
  std::size_t frames_without_truth = 0;  ///< clouds with no detections_3d/<stamp>.json
  /// True boxes that are no box (negative size, zero quaternion...), skipped: file and why.
  std::vector<std::string> invalid_truth;
  /// Frames whose ground was not found ("<stamp>: <why>", groundNotFound): segmented
  /// above a flat plane all the same.
  std::vector<std::string> ground_not_found;
  std::size_t points = 0;          ///< over all clouds
  std::size_t visible = 0;         ///< true objects counted (min_points, view, range)
  std::size_t found = 0;           ///< of those, with a segment centre within max_distance
  std::size_t footprint = 0;       ///< of those, with a segment centre in their footprint
  std::size_t segments = 0;        ///< segments counted (view, range)
  std::size_t false_segments = 0;  ///< of those, matching no true object (of any size)
  /// With a classifier: the same figures over the segments it did not call Background, and
  /// how many segments it called Background.
  std::size_t found_kept = 0;
  std::size_t footprint_kept = 0;
  std::size_t segments_kept = 0;
  std::size_t false_segments_kept = 0;
  std::size_t called_background = 0;
  std::map<std::string, std::size_t> rejected;  ///< segments each gate removed
  std::vector<double> milliseconds;  ///< per frame: ground, segmentation and boxes
  SegmentationEvaluationOptions options;

  /// The recall, footprint and false-segment figures and the time per frame, on `out`.
  void report(std::ostream& out) const;
};

/// Segments every cloud of the bag-to-files folder `frames` (pcd/<stamp>.pcd) with `ground`
/// and `config` and compares the segments with detections_3d/<stamp>.json: greedy one-to-one matching of
/// box centres in x-y, nearest first (matchSegments). Throws std::runtime_error naming the
/// folder or file for a missing folder, a folder without clouds, or an unreadable file.
SegmentationEvaluation evaluateSegmentation(const std::filesystem::path& frames,
                                            const GroundConfig& ground,
                                            const SegmentationStageConfig& config,
                                            const SegmentationEvaluationOptions& options = {});

}  // namespace granular
