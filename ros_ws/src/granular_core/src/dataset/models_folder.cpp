#include "granular_core/dataset/models_folder.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/text.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

bool isPcd(const fs::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  return entry.is_regular_file() && entry.path().extension() == ".pcd" && name[0] != '.';
}

}  // namespace

std::size_t pointsBelow(const ModelCloud& cloud, double z) {
  return static_cast<std::size_t>(std::count_if(
      cloud.points.begin(), cloud.points.end(),
      [z](const pcl::PointXYZ& point) { return point.z < z; }));
}

bool looksBoxCentred(const ModelCloud& cloud) {
  return !cloud.empty() && static_cast<double>(pointsBelow(cloud, kBoxCentredDepth)) >
                               kBoxCentredShare * static_cast<double>(cloud.size());
}

std::vector<LabelledModel> readClassModels(const fs::path& folder) {
  if (fs::is_regular_file(folder)) {
    throw std::runtime_error(folder.string() + ": is a file (a classifier from "
                                               "train_classifier?); the registration methods "
                                               "(icp, icp_nl, ndt) need a models folder written "
                                               "by build_models");
  }
  if (!fs::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": no such models folder");
  }
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (isPcd(entry)) {
      files.push_back(entry.path());
    }
  }
  if (files.empty()) {
    throw std::runtime_error(folder.string() +
                             ": no class models (<Class>.pcd) in this folder");
  }
  std::sort(files.begin(), files.end());
  std::vector<LabelledModel> models;
  for (const fs::path& file : files) {
    LabelledModel model{modelClass(file), readModelPcd(file)};
    if (model.label.empty()) {
      throw std::runtime_error(file.string() + ": not a class model's name (<Class>.pcd, the "
                                               "class written as build_models writes it)");
    }
    if (model.cloud.empty()) {
      throw std::runtime_error(file.string() + ": the model has no points");
    }
    if (looksBoxCentred(model.cloud)) {
      const double fraction = static_cast<double>(pointsBelow(model.cloud, kBoxCentredDepth)) /
                              static_cast<double>(model.cloud.size());
      throw std::runtime_error(
          file.string() + ": " + percent(fraction) +
          " of the model's points lie below z = -0.1 m: it is in a box-centre frame (z = 0 at "
          "half the box's height), not the object frame of the objects (z = 0 on the road, "
          "the object above it). Rebuild the models from objects extracted by "
          "extract_objects (build_models).");
    }
    models.push_back(std::move(model));
  }
  return models;
}

}  // namespace granular
