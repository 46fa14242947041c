#pragma once

#include <filesystem>

#include <granular_core/classification/supervised_classifier.h>

namespace granular_ros {

/// Overlays the keys of a YAML supervised-classifier config file (see config/supervised.yaml:
/// `knn`, `svm`, `histograms`) on `config`; keys the file leaves out keep their values. Throws
/// std::runtime_error naming the file and the key path for an unreadable file, an unknown key
/// or a value of the wrong type. Ranges are checked by granular::validate.
void loadSupervisedConfig(const std::filesystem::path& file, granular::SupervisedConfig& config);

}  // namespace granular_ros
