// What the runs share: the clouds of a frames folder, a percentile of timings, and a list of
// lines in a report.
#pragma once

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "granular_core/ground/ground.h"

namespace granular {
namespace runs {

/// The stamps (file stems) of the clouds in `frames`/pcd/, sorted; hidden files left out.
/// Throws std::runtime_error naming the folder when it is missing or holds no cloud.
inline std::vector<std::string> cloudStamps(const std::filesystem::path& frames) {
  const std::filesystem::path pcd = frames / "pcd";
  if (!std::filesystem::is_directory(pcd)) {
    throw std::runtime_error(pcd.string() + ": no such folder (a bag-to-files folder has pcd/ "
                                            "and detections_3d/)");
  }
  std::vector<std::string> stamps;
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator(pcd)) {
    if (entry.path().extension() == ".pcd" && entry.path().filename().string()[0] != '.') {
      stamps.push_back(entry.path().stem().string());
    }
  }
  if (stamps.empty()) {
    throw std::runtime_error(pcd.string() + ": no clouds");
  }
  std::sort(stamps.begin(), stamps.end());
  return stamps;
}

/// The nearest-rank `percent` percentile of `values`; 0 for none.
inline double percentile(std::vector<double> values, int percent) {
  if (values.empty()) {
    return 0.0;
  }
  const std::size_t rank = (values.size() * static_cast<std::size_t>(percent) + 99) / 100;
  const std::size_t index = rank == 0 ? 0 : rank - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                   values.end());
  return values[index];
}

/// At most 10 of `lines` under "`title` (count):" on `log`; nothing for none.
inline void reportList(std::ostream& log, const char* title,
                       const std::vector<std::string>& lines) {
  constexpr std::size_t kShown = 10;
  if (lines.empty()) {
    return;
  }
  log << title << " (" << lines.size() << "):\n";
  for (std::size_t i = 0; i < lines.size() && i < kShown; ++i) {
    log << "  " << lines[i] << '\n';
  }
  if (lines.size() > kShown) {
    log << "  ... and " << lines.size() - kShown << " more\n";
  }
}

/// checkGround on one frame of an offline run ("<stamp>: <why>" lines). A frame without ground
/// is added to `not_found`. A cloud not in the sensor's frame stops the run (std::runtime_error
/// naming the stamp; its output is never put in place): every frame above such a road would be
/// nonsense. With `allow_other_frames` (the tools' --allow-other-frames) it is added to
/// `not_found` instead and the run goes on.
inline void checkFrameGround(const Cloud& cloud, const GroundPlane& plane, std::size_t inliers,
                             const GroundConfig& config, const std::string& frame_id,
                             const std::string& stamp, bool allow_other_frames,
                             std::vector<std::string>& not_found) {
  const GroundCheck check = checkGround(cloud, plane, inliers, config, frame_id);
  if (check.verdict == GroundCheck::Verdict::kNotSensorFrame && !allow_other_frames) {
    throw std::runtime_error(stamp + ": " + check.problem +
                             "; --allow-other-frames goes on, with a warning per frame");
  }
  if (check.verdict != GroundCheck::Verdict::kGround) {
    not_found.push_back(stamp + ": " + check.problem);
  }
}

}  // namespace runs
}  // namespace granular
