#include "granular_core/runs/segmentation_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "granular_core/cuboids/segment_views.h"
#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/detections.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/extraction/extract_objects.h"
#include "background_decision.h"
#include "run_helpers.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

// Within the counted view and range.
bool counted(const Eigen::Vector3d& centre, const SegmentationEvaluationOptions& options) {
  const double range = centre.head<2>().norm();
  const double azimuth = std::abs(std::atan2(centre.y(), centre.x())) * 180.0 / M_PI;
  return range < options.max_range && azimuth <= options.half_field_of_view_deg;
}

// One frame's figures for a set of segment boxes.
struct FrameScore {
  std::size_t visible = 0;
  std::size_t found = 0;
  std::size_t footprint = 0;
  std::size_t segments = 0;
  std::size_t false_segments = 0;
};

FrameScore scoreFrame(const std::vector<OrientedBox>& boxes,
                      const std::vector<OrientedBox>& truth,
                      const std::vector<OrientedBox>& visible, double max_distance) {
  FrameScore score;
  for (const OrientedBox& box : visible) {
    const Eigen::Isometry3d to_object = box.sensorToObject();
    score.footprint += std::any_of(boxes.begin(), boxes.end(), [&](const OrientedBox& b) {
      const Eigen::Vector3d centre = to_object * b.centre();
      return std::abs(centre.x()) <= box.size().x() / 2 &&
             std::abs(centre.y()) <= box.size().y() / 2;
    });
  }
  const SegmentationMatch found = matchSegments(boxes, visible, max_distance);
  score.visible = found.truth;
  score.found = found.matched_truth;
  // A segment on a true object too small to count is not a false one.
  const SegmentationMatch any = matchSegments(boxes, truth, max_distance);
  score.segments = any.segments;
  score.false_segments = any.unmatched_segments;
  return score;
}

// What evaluateSegmentation --save writes for one frame (see SegmentationEvaluationOptions).
void saveFrame(const fs::path& folder, const std::string& stem, const Cloud& cloud,
               const ObjectSegmentation& result, const std::vector<OrientedBox>& boxes,
               const std::vector<std::string>& labels, DetectionsHeader header) {
  std::vector<Detection> detections;
  for (std::size_t s = 0; s < boxes.size(); ++s) {
    const OrientedBox& box = boxes[s];
    Detection detection;
    detection.id = static_cast<std::int64_t>(s);
    detection.label = labels[s];
    detection.centre = box.centre();
    detection.orientation = box.orientation();
    detection.size = box.size();
    detections.push_back(detection);
  }
  writeFile(folder / (stem + ".json"), detectionsJson(detections, header), "JSON");

  std::vector<std::int32_t> segment_of(cloud.size(), 0);
  for (std::size_t i = 0; i < cloud.size() && i < result.ground.ground.size(); ++i) {
    segment_of[i] = result.ground.ground[i] ? -1 : 0;
  }
  for (std::size_t s = 0; s < result.segments.size(); ++s) {
    for (const std::size_t i : result.segments[s].indices) {
      segment_of[i] = static_cast<std::int32_t>(s + 1);
    }
  }
  std::string content = binaryPcdHeader("x y z height segment", "4 4 4 4 4", "F F F F I",
                                        "1 1 1 1 1", cloud.size());
  constexpr std::size_t kRecord = 5 * 4;
  std::size_t at = content.size();
  content.resize(at + cloud.size() * kRecord);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float height = i < result.ground.heights.size()
                             ? result.ground.heights[i]
                             : std::numeric_limits<float>::quiet_NaN();
    std::memcpy(&content[at], cloud[i].data, 3 * sizeof(float));
    std::memcpy(&content[at + 12], &height, sizeof(float));
    std::memcpy(&content[at + 16], &segment_of[i], sizeof(std::int32_t));
    at += kRecord;
  }
  writeFile(folder / (stem + ".pcd"), content, "PCD");
}

// The stamp of a frame named <secs><9-digit nsecs>, for a frame without a detections file.
DetectionsHeader headerFromName(const std::string& stem) {
  DetectionsHeader header;
  if (stem.size() > 9 && stem.find_first_not_of("0123456789") == std::string::npos) {
    header.secs = std::stoll(stem.substr(0, stem.size() - 9));
    header.nsecs = std::stoll(stem.substr(stem.size() - 9));
  }
  return header;
}

}  // namespace

SegmentationEvaluation evaluateSegmentation(const fs::path& frames, const GroundConfig& ground,
                                            const SegmentationStageConfig& config,
                                            const SegmentationEvaluationOptions& options) {
  FrameSegmenter segmenter(ground, config);  // validates both
  std::vector<fs::path> clouds;
  for (const std::string& stamp : runs::cloudStamps(frames)) {
    clouds.push_back(frames / "pcd" / (stamp + ".pcd"));
  }

  std::optional<OutputFolder> saved;
  if (!options.save.empty()) {
    saved.emplace(options.save, "evaluate_segmentation", options.save_policy,
                  std::vector<fs::path>{frames});
  }
  SegmentationEvaluation evaluation;
  evaluation.options = options;
  for (const fs::path& file : clouds) {
    const Cloud cloud = readPcd(file);
    const std::string stem = file.stem().string();
    const fs::path json = frames / "detections_3d" / (stem + ".json");
    DetectionsHeader header = headerFromName(stem);
    const bool has_truth = fs::exists(json);
    evaluation.frames_without_truth += !has_truth;
    const std::vector<Detection> detections =
        has_truth ? readDetectionsJson(json, &header) : std::vector<Detection>();
    const auto start = std::chrono::steady_clock::now();
    const ObjectSegmentation result = segmenter.segment(cloud);
    if (config.method == SegmentationMethod::kObjects) {
      runs::checkFrameGround(cloud, result.ground.plane, result.ground.inliers, ground,
                             header.frame_id, stem, options.allow_other_frames,
                             evaluation.ground_not_found);
    }
    const std::vector<Segment>& segments = result.segments;
    // The boxes scored and saved: the segments' own, or the cuboids fitted to them.
    std::vector<OrientedBox> frame_boxes;
    for (const Segment& segment : segments) {
      frame_boxes.push_back(segment.box);
    }
    if (options.cuboids != nullptr) {
      const SegmentViews views(cloud, result, config, options.free_space);
      for (std::size_t s = 0; s < segments.size(); ++s) {
        if (const std::optional<FittedCuboid> cuboid = options.cuboids->fit(views.view(s))) {
          frame_boxes[s] = cuboid->box;
        }
      }
    }
    for (const auto& [gate, count] : result.rejected) {
      evaluation.rejected[gate] += count;
    }
    evaluation.milliseconds.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    evaluation.points += cloud.size();

    // The Background decision and the true boxes' point counts crop the frame box by box.
    std::optional<FrameCropper> cropper;
    if (options.classifier || !detections.empty()) {
      cropper.emplace(cloud);
    }
    std::vector<std::string> labels(segments.size(), "unknown");
    std::vector<bool> background(segments.size(), false);
    std::vector<OrientedBox> boxes, kept, truth, visible;
    for (std::size_t s = 0; s < segments.size(); ++s) {
      const OrientedBox& box = frame_boxes[s];
      const bool in_view = counted(box.centre(), options);
      if (options.classifier && (in_view || saved)) {
        const runs::BackgroundDecision decision =
            runs::decideBackground(*options.classifier, *cropper, segments[s].box,
                                   config.background);
        labels[s] = decision.label;
        background[s] = decision.dropped;
      }
      if (!in_view) {
        continue;
      }
      boxes.push_back(box);
      if (options.classifier) {
        if (background[s]) {
          ++evaluation.called_background;
        } else {
          kept.push_back(box);
        }
      }
    }
    if (saved) {
      saveFrame(saved->staging(), stem, cloud, result, frame_boxes, labels, header);
    }
    for (std::size_t d = 0; d < detections.size(); ++d) {
      std::string problem;
      const std::optional<OrientedBox> valid = detectionBox(detections[d], d, problem);
      if (!valid) {
        evaluation.invalid_truth.push_back(json.string() + ": " + problem);
        continue;
      }
      const OrientedBox& box = *valid;
      if (!counted(box.centre(), options)) {
        continue;
      }
      truth.push_back(box);
      if (cropper->crop(box, Eigen::Vector3d::Zero()).size() >= options.min_points) {
        visible.push_back(box);
      }
    }
    const FrameScore all = scoreFrame(boxes, truth, visible, options.max_distance);
    evaluation.visible += all.visible;
    evaluation.found += all.found;
    evaluation.footprint += all.footprint;
    evaluation.segments += all.segments;
    evaluation.false_segments += all.false_segments;
    if (options.classifier) {
      const FrameScore after = scoreFrame(kept, truth, visible, options.max_distance);
      evaluation.found_kept += after.found;
      evaluation.footprint_kept += after.footprint;
      evaluation.segments_kept += after.segments;
      evaluation.false_segments_kept += after.false_segments;
    }
    ++evaluation.frames;
    if (options.progress) {
      options.progress(evaluation.frames, clouds.size());
    }
  }
  if (saved) {
    saved->commit();
  }
  return evaluation;
}

void SegmentationEvaluation::report(std::ostream& out) const {
  const auto share = [](std::size_t a, std::size_t b) {
    return b > 0 ? static_cast<double>(a) / static_cast<double>(b) : 0.0;
  };
  double sum = 0.0;
  for (const double value : milliseconds) {
    sum += value;
  }
  char line[256];
  std::snprintf(line, sizeof(line), "clouds: %zu (%.0f points each on average)\n", frames,
                share(points, frames));
  out << line;
  for (std::size_t i = 0; i < invalid_truth.size() && i < 10; ++i) {
    out << "warning: true box skipped: " << invalid_truth[i] << '\n';
  }
  if (invalid_truth.size() > 10) {
    out << "warning: " << invalid_truth.size() - 10 << " more true boxes skipped\n";
  }
  for (std::size_t i = 0; i < ground_not_found.size() && i < 10; ++i) {
    out << "warning: frame without ground: " << ground_not_found[i] << '\n';
  }
  if (ground_not_found.size() > 10) {
    out << "warning: " << ground_not_found.size() - 10 << " more frames without ground\n";
  }
  if (frames_without_truth > 0) {
    std::snprintf(line, sizeof(line),
                  "warning: %zu of the %zu clouds have no detections_3d/<stamp>.json: no true "
                  "objects there, so all their segments count as matching nothing\n",
                  frames_without_truth, frames);
    out << line;
  }
  if (options.cuboids != nullptr) {
    out << "boxes: cuboids fitted to the segments (a segment's own box where none fits)\n";
  }
  std::snprintf(line, sizeof(line),
                "counted: objects with at least %zu points and segments within %.0f deg of "
                "straight ahead",
                options.min_points, options.half_field_of_view_deg);
  out << line;
  if (options.max_range < 1e9) {
    out << ", nearer than " << options.max_range << " m";
  }
  out << '\n';
  std::snprintf(line, sizeof(line),
                "recall: objects with a segment centre within %.2f m: %zu of %zu (%.3f)\n",
                options.max_distance, found, visible, share(found, visible));
  out << line;
  std::snprintf(line, sizeof(line),
                "footprint: objects with a segment centre in their footprint: %zu (%.3f)\n",
                footprint, share(footprint, visible));
  out << line;
  std::snprintf(line, sizeof(line), "segments: %zu, matching no object: %zu (%.3f)\n",
                segments, false_segments, share(false_segments, segments));
  out << line;
  if (options.classifier) {
    std::snprintf(line, sizeof(line),
                  "after the Background decision (%zu segments called Background):\n"
                  "  recall %zu of %zu (%.3f), footprint %zu (%.3f), segments %zu, matching no "
                  "object %zu (%.3f)\n",
                  called_background, found_kept, visible, share(found_kept, visible),
                  footprint_kept, share(footprint_kept, visible), segments_kept,
                  false_segments_kept, share(false_segments_kept, segments_kept));
    out << line;
  }
  if (!rejected.empty()) {
    out << "removed by the gates:";
    for (const auto& [gate, count] : rejected) {
      out << ' ' << gate << ' ' << count;
    }
    out << '\n';
  }
  std::snprintf(line, sizeof(line), "time per cloud (ground, segments, %s): mean %.2f ms, "
                                    "p95 %.2f ms\n",
                options.cuboids != nullptr ? "cuboids" : "boxes",
                milliseconds.empty() ? 0.0 : sum / static_cast<double>(milliseconds.size()),
                runs::percentile(milliseconds, 95));
  out << line;
}

}  // namespace granular
