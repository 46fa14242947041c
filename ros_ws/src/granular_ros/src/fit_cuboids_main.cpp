// fit_cuboids: the command-line face of granular::fitCuboidsFolder (its options:
// fit_cuboids_options.h).
#include <iostream>
#include <optional>

#include <granular_core/config/fields.h>
#include <granular_core/dataset/models_folder.h>
#include <granular_core/runs/fit_cuboids_run.h>
#include <pcl/console/print.h>

#include "fit_cuboids_options.h"

int main(int argc, char** argv) {
  granular_ros::FitCuboidsOptions options;
  granular::CuboidConfig config;
  granular::FitCuboidsOptions run;
  granular_ros::Tool tool("fit_cuboids");
  options.declareIn(tool);
  const auto configure = [&] {
    config = options.config();
    options.configure(run, config);
  };
  std::optional<granular::SupervisedClassifier> classifier;
  std::optional<granular::ObjectClassifier> namer;
  return tool.run(argc, argv, configure, [&] {
    if (options.classifier_file && !granular_ros::isVehicleDecision(*options.classifier_file)) {
      classifier.emplace(granular_ros::loadBackgroundClassifier(
          *options.classifier_file, run.segmentation.background.label));
      run.classifier = &*classifier;
    }
    if (options.name_with) {
      const auto optionalPath = [](const std::optional<std::string>& path) {
        return path ? std::optional<std::filesystem::path>(*path) : std::nullopt;
      };
      namer.emplace(granular_ros::makeObjectClassifier(
          *options.name_with, *options.name_models, optionalPath(options.class_models),
          optionalPath(options.registration_config), options.preset, options.threads));
      tool.warn(namer->warnings());
      run.namer = &*namer;
    }
    const std::string method = granular::config::enumName(config.method);
    if (options.models && config.method == granular::CuboidMethod::kModel) {
      run.models = granular::readClassModels(*options.models);
    } else if (options.models) {
      tool.warn({"--models is not used by the " + method + " method"});
    }
    if (!options.prior_classes.empty() && config.method != granular::CuboidMethod::kGeometric) {
      tool.warn({"--prior-classes is not used by the " + method + " method"});
    }
    // PCL prints a line for every registration that finds too few pairs.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    run.threads = options.threads;
    run.output = granular_ros::Tool::outputPolicy(options.overwrite);
    run.progress = tool.progress("fitting", "frames");
    granular::fitCuboidsFolder(options.frames, options.out, config, run)
        .report(std::cout, std::cerr);
  });
}
