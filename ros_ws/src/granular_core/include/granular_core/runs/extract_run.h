#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "granular_core/dataset/output_folder.h"
#include "granular_core/extraction/extraction_config.h"
#include "granular_core/ground/ground.h"
#include "granular_core/segmentation/object_segmentation.h"

namespace granular {

/// Background objects for training (extract_objects --background): every frame is segmented
/// as the box-free path does, and the segments on no true box are extracted with their
/// segment's box under segmentation.background.label (labelSegments).
struct BackgroundHarvest {
  GroundConfig ground;
  SegmentationStageConfig segmentation;
  /// The other classes' objects are segments too (labelSegments): the frame's boxes are not
  /// cropped, and each segment on one true box is extracted in its segment's box under that
  /// box's label, as the box-free path will show it to a classifier (extract_objects
  /// --segment-objects).
  bool segment_objects = false;
};

/// How extractFolder runs, apart from the tunables.
struct ExtractFolderOptions {
  /// Whether an output folder of an earlier run may be replaced (see OutputFolder).
  OutputPolicy output;
  /// Write `out/N<thresh>/` even for a single threshold, so that a run's objects folder has the
  /// same layout whatever thresholds it was given (run_pipeline).
  bool threshold_folders = false;
  /// A folder of `<stamp>.json` boxes (fit_cuboids' output for a bag without boxes) used
  /// instead of `in/detections_3d/`; empty: the frames' own.
  std::filesystem::path boxes;
  /// Also extract Background objects; see BackgroundHarvest.
  std::optional<BackgroundHarvest> background;
  /// Called after each frame with (frames done, frames to do); may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// What extractFolder did.
struct ExtractFolderSummary {
  /// Frames with both a PCD and a detections JSON, all of which were extracted.
  std::size_t frames_read = 0;
  /// One line per unpaired file: "<stamp>: <why>".
  std::vector<std::string> frames_skipped;
  /// One line per rejected detection, naming its JSON file.
  std::vector<std::string> invalid_detections;
  /// About the run as a whole, e.g. a requested label that no detection carries.
  std::vector<std::string> warnings;
  std::size_t non_finite_points = 0;
  /// What dead runs had left beside `out` and was cleared (OutputFolder::cleared).
  std::vector<std::string> cleared;
  /// Objects written, per label, for every threshold (sorted, duplicates merged).
  std::map<std::size_t, std::map<std::string, std::size_t>> objects;
  double seconds = 0.0;  ///< wall time of the whole run

  /// What was cleared, warnings, skipped frames and detections (at most 10 lines each) on
  /// `log`; frames per second and the objects per label and threshold as a table on `out`.
  void report(std::ostream& out, std::ostream& log) const;
};

/// Extracts every frame of a bag-to-files folder `in` (`in/pcd/<stamp>.pcd` paired with
/// `in/detections_3d/<stamp>.json`, or options.boxes' `<stamp>.json`, in stamp order) into
/// objects folders under `out`.
///
/// An objects folder holds the object PCDs (named by objectFileName) with at least N_thresh points
/// and an `index.csv` with the columns
/// `file,label,detection_id,stamp,points,range_m,length_m,width_m,height_m,yaw_rad`.
/// With one threshold `out` is that folder (unless options.threshold_folders); with several,
/// `out/N<thresh>/` is one per threshold, all filled in the same pass and sharing files through
/// hard links.
///
/// `out` is an OutputFolder: locked, built in a hidden sibling and renamed into place at the
/// end, so a failure or a signal leaves `out` as it was. A file without its partner is
/// reported, not fatal. Throws std::invalid_argument for a bad config and std::runtime_error
/// (naming the file or folder) for missing input folders, a folder without a single pair,
/// unreadable input files, a detection whose header.frame_id is not its file's (the cloud's,
/// both named), an `out` that may not be replaced (see checkOutputFolder), and write failures.
ExtractFolderSummary extractFolder(const std::filesystem::path& in,
                                   const std::filesystem::path& out,
                                   const ExtractionConfig& config,
                                   const ExtractFolderOptions& options = {});

}  // namespace granular
