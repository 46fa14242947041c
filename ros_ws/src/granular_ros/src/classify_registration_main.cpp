// classify_registration: the command-line face of granular::classifyFolder.
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include <granular_core/runs/classify_registration_run.h>
#include <pcl/console/print.h>

#include "granular_ros/config_file.h"
#include "granular_ros/presets.h"
#include "granular_ros/tool.h"

int main(int argc, char** argv) {
  std::string models, objects, method_name, out, preset = granular_ros::kDefaultPreset;
  std::optional<std::string> config_file;
  granular::ClassifyFolderOptions run;
  bool transforms = false;
  granular_ros::Tool tool(
      "classify_registration",
      "usage: classify_registration --models FOLDER --objects FOLDER --method METHOD\n"
      "                             --out FILE.json [options]\n\n"
      "Registers each object PCD of an objects folder (<Class>-<stamp>-<index>.pcd, object\n"
      "frame) against each class model of a models folder (<Class>.pcd, as build_models\n"
      "writes them) and predicts its class by the report's three criteria (section 8.1):\n"
      "1 the one model it converged to, 2 the converged model of lowest fitness, 3 the model\n"
      "of lowest fitness. Convergence is PCL's convergence state (transformation or error\n"
      "change below its epsilon), not hasConverged(), which is also true when a run merely\n"
      "reaches its iteration limit. Writes FILE.json: per object the fitness, convergence\n"
      "state and iterations against every model (and the final transform, with\n"
      "--transforms), and the three predictions. Needs no roscore.\n",
      "Progress and warnings go to stderr, a summary per criterion to stdout. Exit status:\n"
      "0 done, 1 failed (unreadable or empty folders, models in another frame, output not\n"
      "writable), 2 bad option or configuration, 130/143/129 interrupted by\n"
      "SIGINT/SIGTERM/SIGHUP.\n");
  tool.options()
      .required("--models", models, "FOLDER", "class models (<Class>.pcd)")
      .required("--objects", objects, "FOLDER", "objects to classify")
      .required("--method", method_name, "METHOD",
                "icp (IterativeClosestPoint), icp_nl (IterativeClosestPointNonLinear) or ndt "
                "(NormalDistributionsTransform)")
      .required("--out", out, "FILE.json", "results file to write (replaced)")
      .value("--preset", preset, "NAME", granular_ros::presetHelp())
      .value("--config", config_file, "FILE",
             "YAML file with presets (the repository's config/classification.yaml documents "
             "every parameter)")
      .flag("--transforms", transforms,
            "also write each pair's final transform (16 numbers, row-major; the file grows "
            "about threefold)")
      .threads("--threads", run.registration.threads, "threads (default: every core)")
      .flag("--early-rejection", run.registration.early_rejection,
            "score an object's fitness only against the models that can still be its best or "
            "second best under criterion 2 or 3 (a lower bound of each model's fitness rejects "
            "the others): the same predictions, faster; the rejected pairs' fitness is null "
            "with \"rejected\": true, so svm_fitness cannot learn from the file");
  granular::RegistrationClassifierConfig config;
  granular::RegistrationMethod method{};
  const auto configure = [&] {
    method = granular_ros::parseChoice<granular::RegistrationMethod>("--method", method_name);
    config = granular_ros::resolvePreset(config_file, preset);
  };
  return tool.run(argc, argv, configure, [&] {
    // PCL's line for each registration with too few pairs or no NDT cell: the file has them.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    run.preset = preset;
    run.registration.progress = tool.progress(granular::registrationMethodName(method), "objects");
    run.warn = [&tool](const std::string& warning) { tool.warn({warning}); };
    const granular::ClassificationRun result =
        granular::classifyFolder(models, objects, method, config, run);
    granular::writeClassificationJson(out, result, {transforms});
    result.report(std::cout);
  });
}
