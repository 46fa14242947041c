#include "granular_ros/presets.h"

#include <stdexcept>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"

namespace granular_ros {

granular::RegistrationClassifierConfig resolvePreset(
    const std::optional<std::filesystem::path>& file, const std::string& name) {
  granular::RegistrationPresets presets;
  if (file) {
    loadConfigFile(*file, presets);
  }
  const granular::RegistrationClassifierConfig& preset = presets.preset(name);
  try {
    granular::validate(preset);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("invalid configuration (preset " + name + "): " + error.what());
  }
  return preset;
}

granular::ObjectClassifier makeObjectClassifier(
    const std::string& method, const std::filesystem::path& models,
    const std::optional<std::filesystem::path>& class_models,
    const std::optional<std::filesystem::path>& presets_file, const std::string& preset,
    int threads) {
  if (const auto registration = granular::registrationMethodFromName(method)) {
    return granular::ObjectClassifier::registration(
        *registration, resolvePreset(presets_file, preset), models, threads);
  }
  if (method == "svm_fitness") {
    if (!class_models) {
      throw std::invalid_argument("svm_fitness needs the class models folder it learnt from");
    }
    return granular::ObjectClassifier::fitness(
        models, *class_models,
        [&](const std::string& name) { return resolvePreset(presets_file, name); }, threads);
  }
  if (granular::supervisedMethodFromName(method)) {
    granular::ObjectClassifier classifier = granular::ObjectClassifier::supervised(models, threads);
    if (classifier.method() != method) {
      throw std::invalid_argument(models.string() + " holds a " + classifier.method() +
                                  " classifier, not " + method);
    }
    return classifier;
  }
  throw std::invalid_argument(
      "expected icp, icp_nl, ndt, knn, svm, svm_esf or svm_fitness, got '" + method + "'");
}

std::string presetHelp() {
  const auto presets = granular::registrationPresets();
  const granular::RegistrationClassifierConfig& report = presets.at("report");
  const granular::RegistrationClassifierConfig& tuned = presets.at("tuned");
  return "parameter set: report (the report's values: ICP " + shown(report.icp.max_iterations) +
         " iteration, " + shown(report.icp.max_correspondence_distance) +
         " m; NDT resolution " + shown(report.ndt.resolution) + " m, " +
         shown(report.ndt.max_iterations) +
         " iterations), tuned (chosen on training drives; ICP and ICP-NL first pair points up "
         "to " + shown(tuned.icp.coarse_correspondence_distance) + " m for " +
         shown(tuned.icp.coarse_iterations) + " iterations; at most " +
         shown(tuned.source_max_points) + " points an object) or fast (tuned on at most " +
         shown(presets.at("fast").source_max_points) + " points); default " + kDefaultPreset;
}

}  // namespace granular_ros
