#include "granular_core/extraction/extract_folder.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iomanip>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "granular_core/extraction/detections.h"
#include "granular_core/extraction/extract_objects.h"
#include "granular_core/io/atomic_output.h"
#include "granular_core/io/pcd_io.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

constexpr const char* kIndexHeader =
    "file,label,detection_id,stamp,points,range_m,length_m,width_m,height_m,yaw_rad\n";

// Stems of the files in `folder` with the given extension; sorted, so equal-length numeric
// stamps come out in time order.
std::set<std::string> stems(const fs::path& folder, const std::string& extension) {
  if (!fs::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": no such folder (a bag-to-files folder has " +
                             "pcd/ and detections_3d/)");
  }
  std::set<std::string> result;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file() && entry.path().extension() == extension) {
      result.insert(entry.path().stem().string());
    }
  }
  return result;
}

// Stamps with both files, in order; each unpaired file is added to `skipped` with the reason.
std::vector<std::string> pairStamps(const std::set<std::string>& pcd_stamps,
                                    const std::set<std::string>& json_stamps,
                                    std::vector<std::string>& skipped) {
  std::vector<std::string> paired;
  for (const std::string& stamp : pcd_stamps) {
    if (json_stamps.count(stamp) != 0) {
      paired.push_back(stamp);
    } else {
      skipped.push_back(stamp + ": no detections_3d/" + stamp + ".json");
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
  std::ofstream index;
};

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) {
    return text;
  }
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  }
  return quoted + '"';
}

std::string indexRow(const std::string& file, const ExtractedObject& object,
                     const std::string& stamp) {
  const Eigen::Vector3d& size = object.box.size();
  std::ostringstream row;
  row << csvField(file) << ',' << csvField(object.detection.label) << ','
      << object.detection.id << ',' << csvField(stamp) << ',' << object.cloud.size() << ','
      << std::fixed << std::setprecision(4) << object.box.range() << ',' << size.x() << ','
      << size.y() << ',' << size.z() << ',' << std::setprecision(6) << object.box.yaw() << '\n';
  return row.str();
}

void linkOrCopy(const fs::path& from, const fs::path& to) {
  std::error_code error;
  fs::create_hard_link(from, to, error);
  if (error) {
    fs::copy_file(from, to);
  }
}

// The absolute output path without a trailing separator, so that it has a file name.
fs::path outputPath(const fs::path& out) {
  fs::path path = fs::absolute(out).lexically_normal();
  return path.has_filename() ? path : path.parent_path();
}

}  // namespace

std::string objectFileName(const std::string& label, const std::string& stamp,
                           std::size_t label_index) {
  std::string safe_label = label;
  for (char& c : safe_label) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' ||
                       c == '-';
    if (!plain) {
      c = '_';
    }
  }
  return safe_label + "-" + stamp + "-" + std::to_string(label_index) + ".pcd";
}

ExtractFolderSummary extractFolder(const fs::path& in, const fs::path& out,
                                   const ExtractionConfig& config,
                                   const ExtractFolderOptions& options) {
  validate(config);
  std::vector<std::size_t> thresholds = config.n_thresh;
  std::sort(thresholds.begin(), thresholds.end());
  thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());

  const fs::path pcd_folder = in / "pcd";
  const fs::path json_folder = in / "detections_3d";
  const std::set<std::string> pcd_stamps = stems(pcd_folder, ".pcd");
  const std::set<std::string> json_stamps = stems(json_folder, ".json");

  const fs::path target = outputPath(out);
  checkReplaceable(target, options.overwrite);

  ExtractFolderSummary summary;
  const std::vector<std::string> stamps =
      pairStamps(pcd_stamps, json_stamps, summary.frames_skipped);
  if (stamps.empty()) {
    throw std::runtime_error(in.string() +
                             ": no PCD in pcd/ has a matching JSON in detections_3d/");
  }

  fs::create_directories(target.parent_path());
  const std::string suffix = std::to_string(::getpid());
  StagingFolder staging(target.parent_path() /
                        ("." + target.filename().string() + ".partial-" + suffix));

  std::vector<ObjectsFolder> folders;
  for (const std::size_t threshold : thresholds) {
    fs::path path = staging.path();
    if (thresholds.size() > 1) {
      path /= "N" + std::to_string(threshold);
      fs::create_directory(path);
    }
    summary.objects.try_emplace(threshold);
    std::ofstream index(path / "index.csv");
    index << kIndexHeader;
    folders.push_back({threshold, std::move(path), std::move(index)});
  }

  for (std::size_t frame = 0; frame < stamps.size(); ++frame) {
    const std::string& stamp = stamps[frame];
    const fs::path json_file = json_folder / (stamp + ".json");
    const FrameExtraction extraction = extractObjects(
        readPcd(pcd_folder / (stamp + ".pcd")), readDetectionsJson(json_file), config);
    summary.non_finite_points += extraction.non_finite_points;
    for (const std::string& error : extraction.errors) {
      summary.invalid_detections.push_back(json_file.string() + ": " + error);
    }

    for (const ExtractedObject& object : extraction.objects) {
      if (object.cloud.size() < thresholds.front()) {
        continue;
      }
      const std::string name =
          objectFileName(object.detection.label, stamp, object.label_index);
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

  for (ObjectsFolder& folder : folders) {
    folder.index.close();
    if (!folder.index) {
      throw std::runtime_error((folder.path / "index.csv").string() + ": write failed");
    }
  }

  replaceFolder(staging.path(), target, suffix);
  staging.release();
  return summary;
}

}  // namespace granular
