#include "granular_core/runs/extract_run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iomanip>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "granular_core/dataset/detections.h"
#include "granular_core/extraction/extract_objects.h"
#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/objects_index.h"
#include "granular_core/dataset/output_folder.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/text.h"
#include "run_helpers.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

// Stems of the files in `folder` with the given extension, hidden files (a tool's manifest)
// left out; sorted, so equal-length numeric stamps come out in time order.
std::set<std::string> stems(const fs::path& folder, const std::string& extension) {
  if (!fs::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": no such folder (a bag-to-files folder has " +
                             "pcd/ and detections_3d/)");
  }
  std::set<std::string> result;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && entry.path().extension() == extension && name[0] != '.') {
      result.insert(entry.path().stem().string());
    }
  }
  return result;
}

// Stamps with both files, in order; each unpaired file is added to `skipped` with the reason.
std::vector<std::string> pairStamps(const std::set<std::string>& pcd_stamps,
                                    const std::set<std::string>& json_stamps,
                                    const std::string& json_place,
                                    std::vector<std::string>& skipped) {
  std::vector<std::string> paired;
  for (const std::string& stamp : pcd_stamps) {
    if (json_stamps.count(stamp) != 0) {
      paired.push_back(stamp);
    } else {
      skipped.push_back(stamp + ": no " + json_place + stamp + ".json");
    }
  }
  for (const std::string& stamp : json_stamps) {
    if (pcd_stamps.count(stamp) == 0) {
      skipped.push_back(stamp + ": no pcd/" + stamp + ".pcd");
    }
  }
  return paired;
}


struct ObjectsFolder {
  std::size_t threshold;
  fs::path path;
  std::ostringstream index;  ///< index.csv, written once complete
};

std::string indexRow(const std::string& file, const ExtractedObject& object,
                     const std::string& stamp) {
  ObjectIndexRow row;
  row.file = file;
  row.label = object.detection.label;
  row.detection_id = std::to_string(object.detection.id);
  row.stamp = stamp;
  row.points = object.cloud.size();
  row.range = object.box.range();
  row.length = object.box.size().x();
  row.width = object.box.size().y();
  row.height = object.box.size().z();
  row.yaw = object.box.yaw();
  return objectIndexLine(row);
}

// The segments of a frame as detections, labelled by the true boxes `detections`
// (labelSegments): the background ones under the background label, and, with
// `segment_objects`, the ones on a true box under its label, in place of the true boxes.
// A segment on a true box keeps that box's id (the instance it shows, as index.csv's
// detection_id); a background one is numbered by its place among the frame's segments. A true
// box that cannot be judged on (plausibleDetectionBox refuses it, as extractObjects does) may
// hold any segment, so the frame then gives no Background objects. Returns what was wrong with
// such boxes when `segment_objects` hides them from extractObjects.
std::vector<std::string> harvestSegments(const Cloud& cloud, const std::vector<Segment>& segments,
                                         const BackgroundConfig& config, bool segment_objects,
                                         double max_box_size, std::vector<Detection>& detections) {
  std::vector<OrientedBox> truth;
  std::vector<const Detection*> truth_detection;
  std::vector<std::string> problems;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& detection = detections[i];
    std::string problem;
    if (const std::optional<OrientedBox> box =
            plausibleDetectionBox(detection, i, max_box_size, problem)) {
      truth.push_back(*box);
      truth_detection.push_back(&detection);
      continue;
    }
    if (segment_objects) {
      problems.push_back(problem + "; skipped, and the frame gives no " + config.label +
                         " objects (any segment may lie on the box)");
    }
  }
  const bool judged = truth.size() == detections.size();
  std::vector<Detection> harvested;
  for (const LabelledSegment& labelled : labelSegments(cloud, segments, truth, config)) {
    if ((labelled.truth && !segment_objects) || (!labelled.truth && !judged)) {
      continue;
    }
    const Segment& segment = segments[labelled.segment];
    Detection detection;
    detection.id = labelled.truth ? truth_detection[*labelled.truth]->id
                                  : static_cast<std::int64_t>(labelled.segment);
    detection.label = labelled.truth ? truth_detection[*labelled.truth]->label : config.label;
    detection.centre = segment.box.centre();
    detection.orientation = segment.box.orientation();
    detection.size = segment.box.size();
    harvested.push_back(detection);
  }
  if (segment_objects) {
    detections = std::move(harvested);
  } else {
    detections.insert(detections.end(), harvested.begin(), harvested.end());
  }
  return problems;
}

void linkOrCopy(const fs::path& from, const fs::path& to) {
  std::error_code error;
  fs::create_hard_link(from, to, error);
  if (error) {
    fs::copy_file(from, to);
  }
}

}  // namespace

void ExtractFolderSummary::report(std::ostream& out, std::ostream& log) const {
  using runs::reportList;
  reportList(log, "cleared", cleared);
  reportList(log, "warnings", warnings);
  reportList(log, "frames skipped", frames_skipped);
  reportList(log, "invalid detections skipped", invalid_detections);

  char line[160];
  std::snprintf(line, sizeof(line), "frames: %zu extracted, %zu skipped, %.2f s, %.1f frames/s\n",
                frames_read, frames_skipped.size(), seconds,
                seconds > 0.0 ? static_cast<double>(frames_read) / seconds : 0.0);
  out << line << "invalid detections: " << invalid_detections.size()
      << ", non-finite points: " << non_finite_points << '\n';

  std::map<std::string, std::map<std::size_t, std::size_t>> by_label;
  for (const auto& [threshold, labels] : objects) {
    for (const auto& [label, count] : labels) {
      by_label[label][threshold] = count;
    }
  }
  // The label column as wide as the longest label, so that long real labels keep the table.
  int width = 16;
  for (const auto& [label, counts] : by_label) {
    width = std::max(width, static_cast<int>(label.size()));
  }
  out << "objects per label (columns: at least N points):\n  " << std::left << std::setw(width)
      << "label" << std::right;
  for (const auto& [threshold, labels] : objects) {
    out << ' ' << std::setw(8) << "N" + std::to_string(threshold);
  }
  out << '\n';
  std::map<std::size_t, std::size_t> totals;
  for (const auto& [label, counts] : by_label) {
    out << "  " << std::left << std::setw(width) << label << std::right;
    for (const auto& [threshold, labels] : objects) {
      const auto count = counts.find(threshold);
      const std::size_t value = count == counts.end() ? 0 : count->second;
      totals[threshold] += value;
      out << ' ' << std::setw(8) << value;
    }
    out << '\n';
  }
  out << "  " << std::left << std::setw(width) << "total" << std::right;
  for (const auto& [threshold, labels] : objects) {
    out << ' ' << std::setw(8) << totals[threshold];
  }
  out << '\n';
}

ExtractFolderSummary extractFolder(const fs::path& in, const fs::path& out,
                                   const ExtractionConfig& config,
                                   const ExtractFolderOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(config);
  std::vector<std::size_t> thresholds = config.n_thresh;
  std::sort(thresholds.begin(), thresholds.end());
  thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());

  const fs::path pcd_folder = in / "pcd";
  const fs::path json_folder = options.boxes.empty() ? in / "detections_3d" : options.boxes;
  const std::set<std::string> pcd_stamps = stems(pcd_folder, ".pcd");
  const std::set<std::string> json_stamps = stems(json_folder, ".json");

  ExtractFolderSummary summary;
  // The frames' own boxes are named as the folder layout has them; others by their path.
  const std::string json_place =
      options.boxes.empty() ? std::string("detections_3d/") : (json_folder / "").string();
  const std::vector<std::string> stamps =
      pairStamps(pcd_stamps, json_stamps, json_place, summary.frames_skipped);
  if (stamps.empty()) {
    throw std::runtime_error(in.string() + ": no PCD in pcd/ has a matching JSON in " +
                             json_folder.string());
  }

  OutputFolder output(out, "extract_objects", options.output, {in, json_folder});
  summary.cleared = output.cleared();

  std::vector<ObjectsFolder> folders;
  for (const std::size_t threshold : thresholds) {
    fs::path path = output.staging();
    if (thresholds.size() > 1 || options.threshold_folders) {
      path /= "N" + std::to_string(threshold);
      fs::create_directory(path);
    }
    summary.objects.try_emplace(threshold);
    std::ostringstream index;
    index << objectIndexHeader();
    folders.push_back({threshold, std::move(path), std::move(index)});
  }

  std::optional<FrameSegmenter> segmenter;
  ExtractionConfig frame_config = config;
  if (options.background) {
    segmenter.emplace(options.background->ground, options.background->segmentation);
    if (!config.labels.empty()) {  // the label filter keeps the harvest
      frame_config.labels.push_back(options.background->segmentation.background.label);
    }
  }
  std::set<std::string> seen_labels;  // of every detection, to name them for a label typo
  for (std::size_t frame = 0; frame < stamps.size(); ++frame) {
    const std::string& stamp = stamps[frame];
    const fs::path json_file = json_folder / (stamp + ".json");
    DetectionsHeader header;
    std::vector<Detection> detections = readDetectionsJson(json_file, &header);
    std::map<std::int64_t, std::size_t> boxes_of_id;
    for (const Detection& detection : detections) {
      seen_labels.insert(detection.label);
      ++boxes_of_id[detection.id];
    }
    for (const auto& [id, boxes] : boxes_of_id) {
      if (boxes > 1) {  // a hand edit's copy: the objects keep it, the user must know
        summary.warnings.push_back(json_file.string() + ": detection id " + std::to_string(id) +
                                   " is given to " + std::to_string(boxes) +
                                   " boxes; ids name tracks, which take them for one object");
      }
    }
    // A box in another frame than the cloud's (the file's header) would be cropped as if it
    // were in the cloud's: the run is refused, both frames named. Boxes are moved into the
    // cloud's frame where the transform is known: bag_to_files, with the bag's /tf and
    // /tf_static.
    for (const Detection& detection : detections) {
      if (!detection.frame_id.empty() && !header.frame_id.empty() &&
          detection.frame_id != header.frame_id) {
        throw std::runtime_error(
            json_file.string() + ": detection id " + std::to_string(detection.id) + " '" +
            detection.label + "' is in frame '" + detection.frame_id + "', the cloud in '" +
            header.frame_id + "' (the file's header.frame_id): its crop would be of the wrong "
            "points. Move the boxes into the cloud's frame first: bag_to_files does, with the "
            "bag's /tf or /tf_static (record the transform from '" + detection.frame_id +
            "' to '" + header.frame_id + "' in the bag, e.g. tf2_ros static_transform_publisher)");
      }
    }
    const Cloud cloud = readPcd(pcd_folder / (stamp + ".pcd"));
    if (segmenter) {
      for (const std::string& problem :
           harvestSegments(cloud, segmenter->segment(cloud).segments,
                           options.background->segmentation.background,
                           options.background->segment_objects, config.max_box_size,
                           detections)) {
        summary.invalid_detections.push_back(json_file.string() + ": " + problem);
      }
    }
    const FrameExtraction extraction = extractObjects(cloud, detections, frame_config);
    summary.non_finite_points += extraction.non_finite_points;
    if (!cloud.empty() && extraction.non_finite_points == cloud.size()) {
      // Else it surfaces stages later as "the filters left no points", with no word why.
      summary.warnings.push_back((pcd_folder / (stamp + ".pcd")).string() + ": all " +
                                 std::to_string(cloud.size()) +
                                 " points are NaN or infinite; the frame gives no objects");
    }
    for (const std::string& error : extraction.errors) {
      summary.invalid_detections.push_back(json_file.string() + ": " + error);
    }

    for (const ExtractedObject& object : extraction.objects) {
      if (object.cloud.size() < thresholds.front()) {
        continue;
      }
      std::string name;
      try {
        name = objectFileName(object.detection.label, stamp, object.label_index);
      } catch (const std::invalid_argument& error) {
        summary.invalid_detections.push_back(json_file.string() + ": detection id " +
                                             std::to_string(object.detection.id) + ": " +
                                             error.what());
        continue;
      }
      const std::string row = indexRow(name, object, stamp);
      std::optional<fs::path> written;
      for (ObjectsFolder& folder : folders) {
        if (object.cloud.size() < folder.threshold) {
          break;
        }
        const fs::path file = folder.path / name;
        if (written) {
          linkOrCopy(*written, file);
        } else {
          writePcdBinary(file, object.cloud);
          written = file;
        }
        folder.index << row;
        ++summary.objects[folder.threshold][object.detection.label];
      }
    }
    ++summary.frames_read;
    if (options.progress) {
      options.progress(frame + 1, stamps.size());
    }
  }

  // A requested label that no detection carries is a typo more often than not: a warning,
  // and an error when none of them matched (an empty result would look like a run).
  const std::string seen =
      seen_labels.empty()
          ? std::string()
          : "; labels seen: " +
                joined(std::vector<std::string>(seen_labels.begin(), seen_labels.end()));
  std::vector<std::string> unmatched;
  for (const std::string& label : config.labels) {
    if (seen_labels.count(label) == 0) {
      unmatched.push_back(label);
      summary.warnings.push_back("label '" + label + "' (labels) matches no detection" + seen);
    }
  }
  if (!config.labels.empty() && unmatched.size() == config.labels.size()) {
    throw std::runtime_error(in.string() + ": no detection carries any of the labels asked for (" +
                             joined(config.labels) + ")" + seen);
  }
  for (ObjectsFolder& folder : folders) {
    writeFile(folder.path / "index.csv", folder.index.str(), "index");
  }
  output.commit();
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace granular
