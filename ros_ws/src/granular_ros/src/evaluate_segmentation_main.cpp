// evaluate_segmentation: the occupancy-grid segmentation against ground-truth boxes, over a
// bag-to-files folder (pcd/<stamp>.pcd with detections_3d/<stamp>.json).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/dataset/detections.h>
#include <granular_core/extraction/extract_objects.h>
#include <granular_core/dataset/pcd_io.h>
#include <granular_core/segmentation/occupancy_segmentation.h>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"

namespace {

namespace fs = std::filesystem;

constexpr int kFailed = 1;
constexpr int kBadUsage = 2;

const char* const kUsage =
    "usage: evaluate_segmentation --frames FOLDER [--config FILE] [--max-distance M]\n"
    "                             [--min-points N]\n"
    "\n"
    "Segments every cloud of a bag-to-files folder (pcd/<stamp>.pcd) with the occupancy grid\n"
    "of Himmelsbach et al. (paper defaults: 0.15 m cells, 100 m x 100 m, 0.15 m threshold;\n"
    "--config: a YAML file like config/segmentation.yaml over them)\n"
    "and matches the boxes to the ground truth of detections_3d/<stamp>.json, nearest box\n"
    "centres first, within --max-distance metres in x-y (default 1). Prints how many true\n"
    "objects got a box (all of them, and those with at least --min-points points in the\n"
    "cloud, default 10: the visible ones) and how many visible ones hold a box centre in their\n"
    "footprint (a box of the visible faces of a car seen from behind has its centre on the\n"
    "rear, half a car from the true centre), how many boxes matched nothing, and the time per\n"
    "cloud. Needs no roscore. Exit status: 0 done, 1 unreadable input, 2 bad option.\n";

double percentile95(std::vector<double> values) {
  if (values.empty()) {
    return 0.0;
  }
  const std::size_t rank = (values.size() * 95 + 99) / 100 - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank),
                   values.end());
  return values[rank];
}

}  // namespace

int main(int argc, char** argv) {
  std::string frames;
  double max_distance = 1.0;
  std::size_t min_points = 10;
  granular::SegmentationConfig config;
  try {
    bool help = false;
    std::optional<std::string> config_file;
    granular_ros::OptionTable()
        .help(help)
        .required("--frames", frames)
        .value("--config", config_file)
        .number("--max-distance", max_distance)
        .number("--min-points", min_points)
        .parse(argc, argv);
    if (help) {
      std::cout << kUsage;
      return 0;
    }
    config = granular_ros::buildConfig<granular::SegmentationConfig>(config_file);
  } catch (const std::exception& error) {
    std::cerr << "evaluate_segmentation: " << error.what()
              << "\n(see evaluate_segmentation --help)\n";
    return kBadUsage;
  }

  try {
    std::vector<fs::path> clouds;
    for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(frames) / "pcd")) {
      if (entry.path().extension() == ".pcd") {
        clouds.push_back(entry.path());
      }
    }
    if (clouds.empty()) {
      throw std::runtime_error(frames + "/pcd: no clouds");
    }
    std::sort(clouds.begin(), clouds.end());
    granular::SegmentationMatch all, visible;
    std::size_t covered = 0;  // visible true objects whose footprint holds a box centre
    std::vector<double> milliseconds;
    std::size_t points = 0;
    for (const fs::path& file : clouds) {
      const granular::Cloud cloud = granular::readPcd(file);
      const std::vector<granular::Detection> detections = granular::readDetectionsJson(
          fs::path(frames) / "detections_3d" / (file.stem().string() + ".json"));
      const auto start = std::chrono::steady_clock::now();
      const std::vector<granular::Segment> segments = granular::segmentCloud(cloud, config);
      milliseconds.push_back(std::chrono::duration<double, std::milli>(
                                 std::chrono::steady_clock::now() - start).count());
      points += cloud.size();
      std::vector<granular::OrientedBox> boxes, truth, seen;
      for (const granular::Segment& segment : segments) {
        boxes.push_back(segment.box);
      }
      for (const granular::Detection& detection : detections) {
        const granular::OrientedBox box(detection.centre, detection.orientation, detection.size);
        truth.push_back(box);
        if (granular::cropToObjectFrame(cloud, box, Eigen::Vector3d::Zero()).size() >=
            min_points) {
          seen.push_back(box);
          const Eigen::Isometry3d to_object = box.sensorToObject();
          covered += std::any_of(boxes.begin(), boxes.end(), [&](const granular::OrientedBox& b) {
            const Eigen::Vector3d centre = to_object * b.centre();
            return std::abs(centre.x()) <= box.size().x() / 2 &&
                   std::abs(centre.y()) <= box.size().y() / 2;
          });
        }
      }
      const granular::SegmentationMatch frame = granular::matchSegments(boxes, truth, max_distance);
      const granular::SegmentationMatch frame_seen =
          granular::matchSegments(boxes, seen, max_distance);
      all.truth += frame.truth;
      all.matched_truth += frame.matched_truth;
      all.segments += frame.segments;
      all.unmatched_segments += frame.unmatched_segments;
      visible.truth += frame_seen.truth;
      visible.matched_truth += frame_seen.matched_truth;
    }
    double sum = 0.0;
    for (const double value : milliseconds) {
      sum += value;
    }
    const auto share = [](std::size_t a, std::size_t b) { return b > 0 ? double(a) / b : 0.0; };
    std::printf("clouds: %zu (%.0f points each on average)\n", clouds.size(),
                double(points) / clouds.size());
    std::printf("true objects with a box within %.2f m: %zu of %zu (%.3f); with at least %zu "
                "points: %zu of %zu (%.3f)\n",
                max_distance, all.matched_truth, all.truth, share(all.matched_truth, all.truth),
                min_points, visible.matched_truth, visible.truth,
                share(visible.matched_truth, visible.truth));
    std::printf("true objects with at least %zu points whose footprint holds a box centre: %zu "
                "(%.3f)\n",
                min_points, covered, share(covered, visible.truth));
    std::printf("boxes: %zu, matching no true object: %zu (%.3f)\n", all.segments,
                all.unmatched_segments, share(all.unmatched_segments, all.segments));
    std::printf("time per cloud: mean %.2f ms, p95 %.2f ms\n", sum / milliseconds.size(),
                percentile95(milliseconds));
  } catch (const std::exception& error) {
    std::cerr << "evaluate_segmentation: " << error.what() << '\n';
    return kFailed;
  }
  return 0;
}
