#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/dataset/output_folder.h"
#include "granular_core/online/object_classifier.h"
#include "granular_core/segmentation/object_segmentation.h"
#include "granular_core/supervised/supervised_classifier.h"
#include "granular_core/tracking/tracking_config.h"

namespace granular {

/// Where the objects to fit come from.
enum class CuboidInputs {
  kSegments,    ///< the box-free segmentation's segments; the frame's boxes are never read
  kDetections,  ///< the frame's detection boxes (DetectionPointsConfig), headings unused
};

template <>
struct config::EnumNames<CuboidInputs> {
  static constexpr const char* what = "boxes";
  static constexpr std::array<std::pair<CuboidInputs, const char*>, 2> values{
      {{CuboidInputs::kSegments, "segment"}, {CuboidInputs::kDetections, "detections"}}};
};

/// How fitCuboidsFolder runs, apart from the cuboid config.
struct FitCuboidsOptions {
  CuboidInputs boxes = CuboidInputs::kSegments;
  /// The ground stage (both inputs: its road plane is the ground under the objects);
  /// config/ground.yaml.
  GroundConfig ground;
  /// Whether a cloud whose road is not where the sensor's frame puts it (checkGround: a world
  /// or vehicle frame) is only named among the frames without ground; otherwise it stops the
  /// run with an error naming the frame and the remedies, and nothing is written.
  bool allow_other_frames = false;
  /// The segmentation (kSegments); config/segmentation.yaml.
  SegmentationStageConfig segmentation;
  /// The Background decision (kSegments): a classifier trained with Background objects; the
  /// segments it calls segmentation.background.label get no cuboid, the others its class and
  /// score where the fitter gives no label (kUnknownLabel) and the class is not Background
  /// (kept as not sure enough). Null: the zero-shot vehicle decision (CuboidConfig::evidence,
  /// the objects segmentation only) decides which segments get a cuboid.
  const SupervisedClassifier* classifier = nullptr;
  /// Names each cuboid (either input): the frame's points in the cuboid, in its object frame,
  /// cropped as extractObjects crops a given box (grown by `naming_padding`, ExtractionConfig's
  /// padding), go to this classifier, and its label and score replace the fitter's and the
  /// Background decision's where it classifies the object (enough points for its method), before
  /// tracking votes on them. Null: the cuboids keep the fitter's labels.
  const ObjectClassifier* namer = nullptr;
  Eigen::Vector3d naming_padding = Eigen::Vector3d::Zero();
  /// Tracking (docs/tracking.md): each frame's cuboids, in stamp order, go through a Tracker
  /// with this config, and only the cuboids of its born tracks are written, each with its
  /// track's id, velocity and class so far (label and share; the cuboid's own where no frame
  /// voted yet), by id. Offline, a track's frames before its birth are written too (each
  /// frame is held until the tracks that may still be born from it are). None: every cuboid
  /// as fitted, numbered per frame, at rest.
  std::optional<TrackingConfig> tracking;
  /// The class models, for the model-based method.
  std::vector<LabelledModel> models;
  /// Threads fitting a frame's objects; 0: every core.
  int threads = 0;
  /// Whether an output folder of an earlier run may be replaced (see OutputFolder).
  OutputPolicy output;
  /// Called after each frame with (frames done, frames to do); may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// What fitCuboidsFolder did.
struct FitCuboidsSummary {
  std::string method;  ///< CuboidConfig::method's name
  CuboidInputs boxes = CuboidInputs::kSegments;
  std::size_t frames = 0;   ///< frames written
  std::size_t objects = 0;  ///< segments or valid detections given to the fitter
  std::size_t fitted = 0;   ///< cuboids written (the others had too few points, or no track)
  std::size_t called_background = 0;  ///< segments the classifier called Background
  std::string namer;           ///< the naming classifier's method; empty: none
  std::size_t not_named = 0;   ///< cuboids it could not classify (kept the fitter's label)
  bool tracked = false;         ///< whether the cuboids went through the tracker
  std::size_t tracks = 0;       ///< tracks born
  std::size_t tentative = 0;    ///< cuboids not written: their track was never born
  std::size_t bridging = 0;     ///< cuboids written where a track coasted (bridge_gaps)
  /// Segments the zero-shot vehicle decision (CuboidConfig::evidence, segments without a
  /// classifier) gave no cuboid, by verdict name.
  std::map<std::string, std::size_t> not_vehicles;
  std::map<std::string, std::size_t> labels;  ///< cuboids per label
  /// One line per frame left out ("<stamp>: <why>") and per detection skipped (naming its file).
  std::vector<std::string> frames_skipped;
  std::vector<std::string> invalid_detections;
  /// One line per frame whose ground was not found ("<stamp>: <why>"): fitted all the same
  /// above a flat plane, which a user must know of (groundNotFound).
  std::vector<std::string> ground_not_found;
  std::vector<std::string> cleared;  ///< what dead runs had left beside the output
  /// Per object: milliseconds in CuboidFitter::fit (segmentation, ground and the cropping of
  /// detections not included).
  std::vector<double> milliseconds;
  /// Per frame: milliseconds from its cloud read to its cuboids judged (ground, segmentation,
  /// splitting, cropping, fitting and the vehicle decision; over FitCuboidsOptions::threads).
  std::vector<double> frame_milliseconds;
  double seconds = 0.0;  ///< wall time of the whole run

  /// Cleared, skipped frames and detections, frames without ground (at most 10 lines each) on
  /// `log`; counts, labels
  /// and the time per object (median, p95, max) on `out`.
  void report(std::ostream& out, std::ostream& log) const;
};

/// Fits a cuboid to every object of every frame of the bag-to-files folder `frames`
/// (pcd/<stamp>.pcd, detections_3d/<stamp>.json) with the fitter config.method names, and
/// writes `out/<stamp>.json` per frame: a Detection3DArray in the layout of detections_3d/
/// (detectionsJson), in the sensor frame, the frame's header kept; one detection per cuboid,
/// its label and score the fitter's, its id the detection's (kDetections) or the segment's
/// index in the frame (kSegments), or with options.tracking its track's. A frame's ground is
/// the road plane of the ground stage (options.ground); the occupancy segmentation has none,
/// and its objects stand on their lowest point. With kDetections a cloud without its
/// detections file is skipped and reported, as is a detection whose box is not a box.
///
/// `out` is an OutputFolder (locked, built beside, renamed into place when complete). Throws
/// std::invalid_argument for a bad config or a model-based method without models, and
/// std::runtime_error naming the folder or file for a missing pcd/ folder, a folder without
/// clouds, unreadable input, a frame whose stamp is not after the previous one's when
/// tracking, an `out` that may not be replaced, and write failures.
FitCuboidsSummary fitCuboidsFolder(const std::filesystem::path& frames,
                                   const std::filesystem::path& out, const CuboidConfig& config,
                                   const FitCuboidsOptions& options);

}  // namespace granular
