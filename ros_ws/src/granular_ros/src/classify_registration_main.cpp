// classify_registration: the command-line face of granular::classifyFolder. Registers every
// object of an objects folder against every class model with ICP, ICP-NL or NDT and writes one
// JSON record per object; prints how each of the report's criteria did.
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include <granular_core/runs/classify_registration_run.h>
#include <pcl/console/print.h>

#include "granular_ros/command_line.h"
#include "granular_ros/presets.h"
#include "granular_ros/tool.h"

namespace {

std::string usage() {
  const auto presets = granular::registrationPresets();
  const granular::RegistrationClassifierConfig& report = presets.at("report");
  std::ostringstream text;
  text << "usage: classify_registration --models FOLDER --objects FOLDER --method METHOD\n"
          "                             --out FILE.json [options]\n"
          "\n"
          "Registers each object PCD of an objects folder (<Class>-<stamp>-<index>.pcd, object\n"
          "frame) against each class model of a models folder (<Class>.pcd, as build_models\n"
          "writes them) and predicts its class by the report's three criteria (section 8.1):\n"
          "1 the one model it converged to, 2 the converged model of lowest fitness, 3 the model\n"
          "of lowest fitness. Convergence is PCL's convergence state (transformation or error\n"
          "change below its epsilon), not hasConverged(), which is also true when a run merely\n"
          "reaches its iteration limit. Writes FILE.json: per object the fitness, convergence\n"
          "state and iterations against every model (and the final transform, with\n"
          "--transforms), and the three predictions. Needs no roscore.\n"
          "\n"
          "options:\n"
          "  --models FOLDER   class models (<Class>.pcd)\n"
          "  --objects FOLDER  objects to classify\n"
          "  --method METHOD   icp (IterativeClosestPoint), icp_nl (IterativeClosestPointNon\n"
          "                    Linear) or ndt (NormalDistributionsTransform)\n"
          "  --out FILE.json   results file to write (replaced)\n"
          "  --preset NAME     parameter set: report (the report's values: ICP "
       << report.icp.max_iterations << " iteration, "
       << report.icp.max_correspondence_distance
       << " m;\n"
          "                    NDT resolution "
       << report.ndt.resolution << " m, " << report.ndt.max_iterations
       << " iterations), tuned (chosen on\n"
          "                    training drives; ICP and ICP-NL first pair points up to "
       << presets.at("tuned").icp.coarse_correspondence_distance << " m\n"
          "                    for " << presets.at("tuned").icp.coarse_iterations
       << " iterations; at most " << presets.at("tuned").source_max_points
       << " points an object) or fast\n"
          "                    (tuned on at most "
       << presets.at("fast").source_max_points
       << " points); default "
       << granular_ros::kDefaultPreset << "\n"
          "  --config FILE     YAML file with presets (the repository's\n"
          "                    config/classification.yaml documents every parameter)\n"
          "  --transforms      also write each pair's final transform (16 numbers, row-major;\n"
          "                    the file grows about threefold)\n"
          "  --threads N       threads (default: every core)\n"
          "  --early-rejection score an object's fitness only against the models that can\n"
          "                    still be its best or second best under criterion 2 or 3 (a\n"
          "                    lower bound of each model's fitness rejects the others): the\n"
          "                    same predictions, faster; the rejected pairs' fitness is null\n"
          "                    with \"rejected\": true, so svm_fitness cannot learn from the file\n"
          "  -h, --help        print this help and exit\n"
          "\n"
          "Progress and warnings go to stderr, a summary per criterion to stdout. Exit status:\n"
          "0 done, 1 failed (unreadable or empty folders, models in another frame, output not\n"
          "writable), 2 bad option or configuration, 130/143/129 interrupted by\n"
          "SIGINT/SIGTERM/SIGHUP.\n";
  return text.str();
}

struct Options {
  std::string models;
  std::string objects;
  std::string method;
  std::string out;
  std::string preset = granular_ros::kDefaultPreset;
  std::optional<std::string> config_file;
  int threads = 0;
  bool transforms = false;
  bool early_rejection = false;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::RegistrationClassifierConfig config;
  granular::RegistrationMethod method{};
  granular_ros::Tool tool("classify_registration", usage);
  tool.options()
      .required("--models", options.models)
      .required("--objects", options.objects)
      .required("--method", options.method)
      .required("--out", options.out)
      .value("--preset", options.preset)
      .value("--config", options.config_file)
      .flag("--transforms", options.transforms)
      .flag("--early-rejection", options.early_rejection)
      .threads("--threads", options.threads);
  const auto configure = [&] {
    const auto parsed = granular::registrationMethodFromName(options.method);
    if (!parsed) {
      throw std::invalid_argument("--method: expected icp, icp_nl or ndt, got '" +
                                  options.method + "'");
    }
    method = *parsed;
    config = granular_ros::resolvePreset(options.config_file, options.preset);
  };
  return tool.run(argc, argv, configure, [&] {
    // PCL prints a line for every registration that finds too few pairs or no NDT cell; the
    // results file records those states.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    granular::ClassifyFolderOptions run_options;
    run_options.preset = options.preset;
    run_options.registration.threads = options.threads;
    run_options.registration.early_rejection = options.early_rejection;
    run_options.registration.progress =
        tool.progress(granular::registrationMethodName(method), "objects");
    run_options.warn = [](const std::string& warning) {
      std::cerr << "classify_registration: warning: " << warning << '\n';
    };
    const granular::ClassificationRun run =
        granular::classifyFolder(options.models, options.objects, method, config, run_options);
    granular::ClassificationJsonOptions json_options;
    json_options.transforms = options.transforms;
    granular::writeClassificationJson(options.out, run, json_options);
    run.report(std::cout);
  });
}
