#include "granular_core/runs/fit_cuboids_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/detections.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/cuboids/frame_cuboids.h"
#include "granular_core/cuboids/segment_views.h"
#include "granular_core/extraction/extract_objects.h"
#include "granular_core/tracking/tracker.h"
#include "background_decision.h"
#include "run_helpers.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

// A header from a stamp in nanoseconds, as bag to files names its files; zero otherwise.
DetectionsHeader headerOfStamp(const std::string& stamp) {
  DetectionsHeader header;
  if (!stamp.empty() && stamp.size() <= 19 &&
      std::all_of(stamp.begin(), stamp.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const long long nanoseconds = std::stoll(stamp);
    header.secs = nanoseconds / 1000000000LL;
    header.nsecs = nanoseconds % 1000000000LL;
  }
  return header;
}

// A frame's cuboids, written once the tracks that may still be born from them have been.
struct PendingFrame {
  std::string stamp;
  DetectionsHeader header;
  std::vector<Detection> fitted;   // every cuboid fitted in the frame
  std::vector<Detection> written;  // those to write: with tracking, the tracks' only
  std::size_t bridging = 0;        // of those, written where their track had no cuboid
};

double seconds(const DetectionsHeader& header) {
  return static_cast<double>(header.secs) + 1e-9 * static_cast<double>(header.nsecs);
}

// Writes into the frames between `before` (the track's last cuboid, `gap` + 1 frames back in
// `pending`) and `after` (this frame's) a cuboid moved evenly between the two by stamp, turned
// as `after`: the track coasted through them. Nothing where `before` is no longer pending.
void bridgeGap(std::deque<PendingFrame>& pending, std::size_t gap, const Detection& after) {
  if (gap + 2 > pending.size()) {
    return;
  }
  const std::size_t last = pending.size() - 1;
  const PendingFrame& start = pending[last - gap - 1];
  const auto found = std::find_if(start.written.begin(), start.written.end(),
                                  [&](const Detection& cuboid) { return cuboid.id == after.id; });
  if (found == start.written.end()) {
    return;
  }
  const Detection before = *found;
  const double t0 = seconds(start.header), t1 = seconds(pending[last].header);
  for (std::size_t k = last - gap; k < last; ++k) {
    const double share = (seconds(pending[k].header) - t0) / (t1 - t0);
    Detection cuboid = after;
    cuboid.centre = before.centre + share * (after.centre - before.centre);
    cuboid.size = before.size + share * (after.size - before.size);
    pending[k].written.push_back(cuboid);
    ++pending[k].bridging;
  }
}

// `cuboid` as the track's: its id, velocity and class (where a frame voted), turned to the
// track's smoothed yaw where that turns it by at most `max_turn_deg` (turnToTrack).
Detection trackCuboid(const Track& track, Detection cuboid, double max_turn_deg) {
  cuboid.orientation = turnToTrack(track, OrientedBox(cuboid.centre, cuboid.orientation,
                                                      cuboid.size),
                                   max_turn_deg) *
                       cuboid.orientation;
  cuboid.id = track.id;
  cuboid.velocity = Eigen::Vector3d(track.velocity.x(), track.velocity.y(), 0.0);
  if (track.share > 0.0) {
    cuboid.label = track.label;
    cuboid.score = track.share;
  }
  return cuboid;
}

// Tracks `frame` (the last of `pending`): its cuboids of reported tracks go to its written
// list, a track born in it adds its tentative frames' cuboids to theirs, and one that coasted
// through at most bridge_frames frames bridges them (offline, those frames are still pending:
// `pending` holds enough of the last frames for both). Returns the reported tracks.
std::vector<Track> trackFrame(Tracker& tracker, const TrackingConfig& config,
                              const fs::path& cloud, std::deque<PendingFrame>& pending,
                              const std::vector<Observation>& observations) {
  PendingFrame& frame = pending.back();
  const double stamp = seconds(frame.header);
  std::vector<Track> tracks;
  try {
    tracks = tracker.update(stamp, observations);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(cloud.string() + ": tracking needs frames in increasing stamps: " +
                             error.what());
  }
  for (const Track& track : tracks) {
    if (track.observation) {  // none while coasting
      frame.written.push_back(
          trackCuboid(track, frame.fitted[*track.observation], config.max_turn_deg));
      if (track.gap > 0 && track.gap <= config.bridge_frames) {
        bridgeGap(pending, track.gap, frame.written.back());
      }
    }
    for (const EarlierObservation& before : track.earlier_observations) {
      PendingFrame& earlier = pending[pending.size() - 1 - before.frames_before];
      earlier.written.push_back(
          trackCuboid(track, earlier.fitted[before.observation], config.max_turn_deg));
    }
  }
  return tracks;
}

// A track's class as it ended: its label and share in the last frame it had a vote.
using FinalClasses = std::map<std::int64_t, std::pair<std::string, double>>;

// Rewrites the written frames `stamps` in `folder` where a cuboid's label or score is not its
// track's final class (TrackingConfig::final_class), moving its count in `labels`.
void writeFinalClasses(const fs::path& folder, const std::vector<std::string>& stamps,
                       const FinalClasses& final_classes,
                       std::map<std::string, std::size_t>& labels) {
  for (const std::string& stamp : stamps) {
    const fs::path file = folder / (stamp + ".json");
    DetectionsHeader header;
    std::vector<Detection> cuboids = readDetectionsJson(file, &header);
    bool changed = false;
    for (Detection& cuboid : cuboids) {
      const auto final_class = final_classes.find(cuboid.id);
      if (final_class == final_classes.end() ||
          (cuboid.label == final_class->second.first &&
           cuboid.score == final_class->second.second)) {
        continue;
      }
      --labels[cuboid.label];
      ++labels[final_class->second.first];
      cuboid.label = final_class->second.first;
      cuboid.score = final_class->second.second;
      changed = true;
    }
    if (changed) {
      writeFile(file, detectionsJson(cuboids, header), "JSON");
    }
  }
  for (auto label = labels.begin(); label != labels.end();) {
    label = label->second == 0 ? labels.erase(label) : std::next(label);
  }
}

// The namer's class for each cuboid of a frame, and for its observation: the frame's points in
// the cuboid, in its object frame, cropped as extractObjects crops a given box, so that box-free
// objects reach the classifier as given ones do. Returns how many it could not classify.
std::size_t nameCuboids(const ObjectClassifier& namer, const FrameCropper& frame,
                        const Eigen::Vector3d& padding, std::vector<Detection>& cuboids,
                        std::vector<Observation>& observations) {
  std::vector<Cloud> objects;
  objects.reserve(cuboids.size());
  for (const Detection& cuboid : cuboids) {
    const Detection away = facingAwayFromSensor(cuboid);
    objects.push_back(frame.crop(OrientedBox(away.centre, away.orientation, away.size), padding));
  }
  const std::vector<ObjectPrediction> predictions = namer.classify(objects);
  std::size_t not_named = 0;
  for (std::size_t i = 0; i < cuboids.size(); ++i) {
    if (!predictions[i].classified) {
      ++not_named;
      continue;
    }
    cuboids[i].label = observations[i].label = predictions[i].label;
    cuboids[i].score = observations[i].score = predictions[i].score;
  }
  return not_named;
}

}  // namespace

void FitCuboidsSummary::report(std::ostream& out, std::ostream& log) const {
  using runs::percentile;
  using runs::reportList;
  reportList(log, "cleared", cleared);
  reportList(log, "frames skipped", frames_skipped);
  reportList(log, "invalid detections skipped", invalid_detections);
  reportList(log, "frames without ground", ground_not_found);
  char line[200];
  std::snprintf(line, sizeof(line),
                "%s fitting of %s: %zu frames, %zu objects, %zu cuboids, %.2f s\n",
                method.c_str(), boxes == CuboidInputs::kSegments ? "segments" : "detections",
                frames, objects, fitted, seconds);
  out << line;
  if (tracked) {
    out << "  tracks born: " << tracks << "; cuboids of tracks never born, not written: "
        << tentative << "; cuboids bridging frames a track coasted through: " << bridging
        << '\n';
  }
  if (!namer.empty()) {
    out << "  named by " << namer << "; too few points to name (the fitter's label kept): "
        << not_named << '\n';
  }
  if (called_background > 0) {
    out << "  segments called Background (no cuboid): " << called_background << '\n';
  }
  if (!not_vehicles.empty()) {
    std::size_t total = 0;
    std::string reasons;
    for (const auto& [verdict, count] : not_vehicles) {
      total += count;
      reasons += (reasons.empty() ? "" : ", ") + verdict + " " + std::to_string(count);
    }
    out << "  segments judged no vehicle (no cuboid): " << total << " (" << reasons << ")\n";
  }
  for (const auto& [label, count] : labels) {
    out << "  " << label << ": " << count << '\n';
  }
  std::snprintf(line, sizeof(line), "ms per object: median %.3f, p95 %.3f, max %.3f\n",
                percentile(milliseconds, 50), percentile(milliseconds, 95),
                milliseconds.empty() ? 0.0
                                     : *std::max_element(milliseconds.begin(),
                                                         milliseconds.end()));
  out << line;
  std::snprintf(line, sizeof(line),
                "ms per frame (ground, segments or crops, cuboids, vehicle decision): median "
                "%.2f, p95 %.2f\n",
                percentile(frame_milliseconds, 50), percentile(frame_milliseconds, 95));
  out << line;
}

FitCuboidsSummary fitCuboidsFolder(const fs::path& frames, const fs::path& out,
                                   const CuboidConfig& config, const FitCuboidsOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(config);
  validate(options.ground);
  validate(options.segmentation);
  const std::unique_ptr<CuboidFitter> fitter = makeCuboidFitter(config, options.models);
  const std::vector<std::string> stamps = runs::cloudStamps(frames);
  FitCuboidsSummary summary;
  summary.method = config::enumName(config.method);
  summary.boxes = options.boxes;
  if (options.namer != nullptr) {
    summary.namer = options.namer->method();
  }
  OutputFolder output(out, "fit_cuboids", options.output, {frames});
  summary.cleared = output.cleared();
  FrameSegmenter segmenter(options.ground, options.segmentation);
  std::optional<Tracker> tracker;
  // Frames not written yet: a track born later may still add cuboids to them.
  std::deque<PendingFrame> pending;
  if (options.tracking) {
    tracker.emplace(*options.tracking);
    summary.tracked = true;
  }
  std::vector<std::string> written_stamps;
  FinalClasses final_classes;
  const auto write = [&](PendingFrame& frame) {
    if (tracker) {  // by track id; untracked, the cuboids stay in the order they were fitted
      std::sort(frame.written.begin(), frame.written.end(),
                [](const Detection& a, const Detection& b) { return a.id < b.id; });
    }
    for (const Detection& cuboid : frame.written) {
      ++summary.labels[cuboid.label];
    }
    summary.fitted += frame.written.size();
    written_stamps.push_back(frame.stamp);
    summary.tentative += frame.fitted.size() - (frame.written.size() - frame.bridging);
    summary.bridging += frame.bridging;
    writeFile(output.staging() / (frame.stamp + ".json"),
              detectionsJson(frame.written, frame.header), "JSON");
    ++summary.frames;
  };

  for (std::size_t frame = 0; frame < stamps.size(); ++frame) {
    const std::string& stamp = stamps[frame];
    const fs::path json = frames / "detections_3d" / (stamp + ".json");
    const bool has_json = fs::exists(json);
    if (options.boxes == CuboidInputs::kDetections && !has_json) {
      summary.frames_skipped.push_back(stamp + ": no detections_3d/" + stamp + ".json");
      continue;
    }
    DetectionsHeader header = headerOfStamp(stamp);
    std::vector<Detection> detections;
    if (has_json && options.boxes == CuboidInputs::kDetections) {
      detections = readDetectionsJson(json, &header);
    } else if (has_json) {
      // Segments need only the file's header (its frame_id), never its boxes: a file that
      // does not read is named, and the header taken from the stamp.
      try {
        readDetectionsJson(json, &header);
      } catch (const std::runtime_error& error) {
        header = headerOfStamp(stamp);
        summary.invalid_detections.push_back(std::string(error.what()) +
                                             "; its header taken from the stamp");
      }
    }
    const Cloud cloud = readPcd(frames / "pcd" / (stamp + ".pcd"));
    const auto frame_begin = std::chrono::steady_clock::now();

    // The objects fitted (given boxes, or segments the Background decision keeps) and the
    // Background decision on each (segments with a classifier only).
    std::vector<FrameObject> objects;
    std::vector<runs::BackgroundDecision> decisions;
    ObjectSegmentation segmentation;
    std::optional<SegmentViews> segment_views;
    std::optional<FreeSpace> free_space;
    FrameCuboidsOptions fit_options;
    fit_options.threads = options.threads;
    FrameCuboids cuboids;
    // Given boxes, the Background decision on segments, or the namer crop the frame box by box.
    std::optional<FrameCropper> cropper;
    if (options.boxes != CuboidInputs::kSegments || options.classifier != nullptr ||
        options.namer != nullptr) {
      cropper.emplace(cloud);
    }
    if (options.boxes == CuboidInputs::kSegments) {
      segmentation = segmenter.segment(cloud);
      if (options.segmentation.method == SegmentationMethod::kObjects) {
        runs::checkFrameGround(cloud, segmentation.ground.plane, segmentation.ground.inliers,
                               options.ground, header.frame_id, stamp,
                               options.allow_other_frames, summary.ground_not_found);
      }
      if (options.classifier == nullptr) {
        // The zero-shot vehicle decision, as the online node makes it.
        cuboids = fitSegmentCuboids(cloud, segmentation, options.segmentation, config, *fitter,
                                    options.threads);
      } else {
        segment_views.emplace(cloud, segmentation, options.segmentation, config.free_space);
        for (std::size_t s = 0; s < segmentation.segments.size(); ++s) {
          const runs::BackgroundDecision decision =
              runs::decideBackground(*options.classifier, *cropper, segmentation.segments[s].box,
                                     options.segmentation.background);
          if (decision.dropped) {
            ++summary.called_background;
            continue;
          }
          objects.push_back({static_cast<std::int64_t>(s), segment_views->view(s)});
          decisions.push_back(decision);
        }
        cuboids = fitFrameObjects(objects, *fitter, fit_options);
      }
    } else {
      std::size_t inliers = 0;
      const GroundPlane ground =
          estimateGroundPlane(cloud, options.ground.plane, nullptr, &inliers);
      runs::checkFrameGround(cloud, ground, inliers, options.ground, header.frame_id, stamp,
                             options.allow_other_frames, summary.ground_not_found);
      free_space.emplace(cloud, ground, config.free_space);
      const Eigen::Vector3d margin = Eigen::Vector3d::Constant(config.detections.margin);
      for (std::size_t d = 0; d < detections.size(); ++d) {
        const Detection& detection = detections[d];
        std::string problem;
        const std::optional<OrientedBox> box = detectionBox(detection, d, problem);
        if (!box) {
          summary.invalid_detections.push_back(json.string() + ": " + problem);
          continue;
        }
        const Eigen::Isometry3d to_sensor = box->sensorToObject().inverse();
        std::vector<Eigen::Vector3d> grown;
        for (const PointXYZIT& point : cropper->crop(*box, margin)) {
          grown.push_back(to_sensor * Eigen::Vector3d(point.x, point.y, point.z));
        }
        FrameObject object;
        object.id = detection.id;
        object.view.ground = ground;
        object.view.points = isolateObject(grown, ground, box->centre(), box->size(), config);
        object.view.free_space = &*free_space;
        objects.push_back(std::move(object));
      }
      cuboids = fitFrameObjects(objects, *fitter, fit_options);
    }

    summary.frame_milliseconds.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_begin)
            .count());
    summary.objects += cuboids.fitted_objects;
    summary.milliseconds.insert(summary.milliseconds.end(), cuboids.milliseconds.begin(),
                                cuboids.milliseconds.end());
    for (const auto& [verdict, count] : cuboids.not_vehicles) {
      summary.not_vehicles[verdict] += count;
    }
    PendingFrame pending_frame{stamp, header, {}, {}};
    std::vector<Observation> observations;
    for (const FrameCuboid& kept : cuboids.kept) {
      Detection cuboid;
      cuboid.id = kept.id;
      cuboid.label = kept.cuboid.label;
      cuboid.score = kept.cuboid.score;
      // The Background decision's class where the fit gives none, unless that class is
      // Background itself (a segment kept as not sure enough, or too far and sparse to judge).
      if (cuboid.label == kUnknownLabel && !decisions.empty() &&
          decisions[kept.object].label != options.segmentation.background.label) {
        cuboid.label = decisions[kept.object].label;
        cuboid.score = decisions[kept.object].score;
      }
      cuboid.centre = kept.cuboid.box.centre();
      cuboid.orientation = kept.cuboid.box.orientation();
      cuboid.size = kept.cuboid.box.size();
      pending_frame.fitted.push_back(cuboid);
      observations.push_back(
          Observation{kept.cuboid.box, cuboid.label, cuboid.score, kept.cuboid.points});
    }
    if (options.namer != nullptr) {
      summary.not_named += nameCuboids(*options.namer, *cropper, options.naming_padding,
                                       pending_frame.fitted, observations);
    }
    pending.push_back(std::move(pending_frame));
    std::size_t held_frames = 0;
    if (tracker) {
      for (const Track& track : trackFrame(*tracker, *options.tracking,
                                           frames / "pcd" / (stamp + ".pcd"), pending,
                                           observations)) {
        if (track.share > 0.0) {
          final_classes[track.id] = {track.label, track.share};
        }
      }
      summary.tracks = tracker->born();
      // A track born in the next frame may write back to its tentative frames, and one that
      // coasted bridge_frames frames bridges them from its cuboid before those.
      held_frames = std::max(tracker->tentativeReach(), options.tracking->bridge_frames) + 1;
    } else {
      pending.back().written = pending.back().fitted;
    }
    while (pending.size() > held_frames) {
      write(pending.front());
      pending.pop_front();
    }
    if (options.progress) {
      options.progress(frame + 1, stamps.size());
    }
  }
  for (; !pending.empty(); pending.pop_front()) {
    write(pending.front());
  }
  if (tracker && options.tracking->final_class) {
    writeFinalClasses(output.staging(), written_stamps, final_classes, summary.labels);
  }
  output.commit();
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace granular
