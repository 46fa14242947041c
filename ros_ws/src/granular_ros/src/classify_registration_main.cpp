// classify_registration: the command-line face of granular::classifyFolder. Registers every
// object of an objects folder against every class model with ICP, ICP-NL or NDT and writes one
// JSON record per object; prints how each of the report's criteria did.
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include <granular_core/classification/classify_folder.h>
#include <pcl/console/print.h>

#include "granular_ros/classification_config_yaml.h"
#include "granular_ros/command_line.h"
#include "granular_ros/tool.h"

namespace {

std::string usage() {
  const granular::RegistrationClassifierConfig report;
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
          "state, iterations and final transform against every model, and the three\n"
          "predictions. Needs no roscore.\n"
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
       << " iterations) or tuned (chosen on a\n"
          "                    training drive); default report\n"
          "  --config FILE     YAML file with presets (the repository's\n"
          "                    config/classification.yaml documents every parameter)\n"
          "  --threads N       threads (default: every core)\n"
          "  --help            print this help and exit\n"
          "\n"
          "Progress and warnings go to stderr, a summary per criterion to stdout. Exit status:\n"
          "0 done, 1 failed (unreadable or empty folders, models in another frame, output not\n"
          "writable), 2 bad option or configuration.\n";
  return text.str();
}

struct Options {
  std::string models;
  std::string objects;
  std::string method;
  std::string out;
  std::string preset = "report";
  std::optional<std::string> config_file;
  int threads = 0;
};

// The built-in presets, then the YAML file's, then the one chosen.
granular::RegistrationClassifierConfig buildConfig(const Options& options) {
  std::map<std::string, granular::RegistrationClassifierConfig> presets =
      granular::registrationPresets();
  if (options.config_file) {
    granular_ros::loadRegistrationPresets(*options.config_file, presets);
  }
  const auto preset = presets.find(options.preset);
  if (preset == presets.end()) {
    std::string known;
    for (const auto& [name, unused] : presets) {
      known += (known.empty() ? "" : ", ") + name;
    }
    throw std::invalid_argument("--preset: no preset '" + options.preset + "' (known: " +
                                known + ")");
  }
  try {
    granular::validate(preset->second);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("invalid configuration (preset " + options.preset +
                                "): " + error.what());
  }
  return preset->second;
}

void printSummary(const granular::ClassificationRun& run) {
  std::printf("%s (%s): %zu objects against %zu models in %.2f s on %d threads\n",
              granular::registrationMethodName(run.method), run.preset.c_str(),
              run.objects.size(), run.models.size(), run.seconds, run.threads);
  for (int criterion = 1; criterion <= 3; ++criterion) {
    const granular::CriterionSummary summary = run.summary(criterion);
    std::printf("  criterion %d: %zu predicted, %zu without a prediction, accuracy %.3f of "
                "the predicted\n",
                criterion, summary.predicted, summary.missing, summary.accuracy());
  }
}

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
      .threads("--threads", options.threads);
  const auto configure = [&] {
    const auto parsed = granular::registrationMethodFromName(options.method);
    if (!parsed) {
      throw std::invalid_argument("--method: expected icp, icp_nl or ndt, got '" +
                                  options.method + "'");
    }
    method = *parsed;
    config = buildConfig(options);
  };
  return tool.run(argc, argv, configure, [&] {
    // PCL prints a line for every registration that finds too few pairs or no NDT cell; the
    // results file records those states.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    granular::ClassifyFolderOptions run_options;
    run_options.preset = options.preset;
    run_options.registration.threads = options.threads;
    run_options.registration.progress =
        tool.progress(granular::registrationMethodName(method), "objects");
    run_options.warn = [](const std::string& warning) {
      std::cerr << "classify_registration: warning: " << warning << '\n';
    };
    const granular::ClassificationRun run =
        granular::classifyFolder(options.models, options.objects, method, config, run_options);
    granular::writeClassificationJson(options.out, run);
    printSummary(run);
  });
}
