#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <granular_core/online/object_classifier.h>
#include <granular_core/registration/registration_config.h>

namespace granular_ros {

/// The registration preset that the tools and the online node run when none is named: the
/// tuned one (the report's ICP never converges; see docs/classification.md).
inline constexpr const char* kDefaultPreset = "tuned";

/// The preset called `name` among the built-in ones with the presets of `file` (a YAML file
/// like config/classification.yaml) laid over them, validated. Throws std::invalid_argument
/// naming the known presets for an unknown name, or the preset and field for a value out of
/// range, and std::runtime_error naming the file and key for a bad file.
granular::RegistrationClassifierConfig resolvePreset(
    const std::optional<std::filesystem::path>& file, const std::string& name);

/// The classifier `method` names (icp, icp_nl, ndt: registration against the models folder
/// `models` with the preset `preset` of `presets_file`; knn, svm, svm_esf: the classifier file
/// `models`; svm_fitness: the file `models` and the models folder it learnt from,
/// `class_models`), as the tools that name box-free objects build it. Throws
/// std::invalid_argument for an unknown method, a file of another method, or svm_fitness without
/// `class_models`, and std::runtime_error naming a file that cannot be read.
granular::ObjectClassifier makeObjectClassifier(
    const std::string& method, const std::filesystem::path& models,
    const std::optional<std::filesystem::path>& class_models,
    const std::optional<std::filesystem::path>& presets_file, const std::string& preset,
    int threads);

/// The --preset option's help: the built-in presets, what sets them apart, and the default.
std::string presetHelp();

}  // namespace granular_ros
