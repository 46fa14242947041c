// classify_supervised: classifies every object of an objects folder with a model written by
// train_classifier and writes one JSON record per object.
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include <granular_core/runs/classify_supervised_run.h>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

const char* const kUsage =
    "usage: classify_supervised --model MODEL.yml --objects FOLDER --out FILE.json [options]\n"
    "\n"
    "Classifies each object PCD of an objects folder (<Class>-<stamp>-<index>.pcd, object\n"
    "frame) with a classifier written by train_classifier, computing the features with the\n"
    "settings stored in the model. Writes FILE.json: per object its true label (from the name)\n"
    "and the prediction; the wall time and the microseconds per object (features and\n"
    "prediction, on one core). Needs no roscore.\n"
    "\n"
    "options:\n"
    "  --model MODEL.yml  classifier to use\n"
    "  --objects FOLDER   objects to classify\n"
    "  --out FILE.json    results file to write (replaced)\n"
    "  --config FILE      YAML file with the feature settings you expect (config/\n"
    "                     supervised.yaml); a model trained with other settings is refused\n"
    "  --threads N        threads (default: every core)\n"
    "  --help             print this help and exit\n"
    "\n"
    "Exit status: 0 done, 1 failed (unreadable model or folder, output not writable), 2 bad\n"
    "option, configuration, or a model of other feature settings than --config.\n";

struct Options {
  std::string model;
  std::string objects;
  std::string out;
  std::optional<std::string> config_file;
  int threads = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::optional<granular::SupervisedConfig> expected;
  granular_ros::Tool tool("classify_supervised", [] { return std::string(kUsage); });
  tool.options()
      .required("--model", options.model)
      .required("--objects", options.objects)
      .required("--out", options.out)
      .value("--config", options.config_file)
      .threads("--threads", options.threads);
  const auto configure = [&] {
    if (options.config_file) {
      expected = granular_ros::buildConfig<granular::SupervisedConfig>(options.config_file);
    }
  };
  return tool.run(argc, argv, configure, [&] {
    const granular::SupervisedClassifier classifier =
        granular::SupervisedClassifier::load(options.model);
    if (expected) {
      const std::string difference = granular::featureConfigDifference(
          classifier.method(), classifier.config().histograms, expected->histograms);
      if (!difference.empty()) {
        throw granular_ros::UsageError(
            options.model + " was trained with other feature settings than " +
            *options.config_file + " (histograms." + difference +
            "); retrain it, or leave --config out to use the model's own");
      }
    }
    const std::string method = granular::supervisedMethodName(classifier.method());
    const granular::SupervisedRun run = granular::classifyFolderSupervised(
        classifier, options.objects, options.threads, tool.progress(method, "objects"));
    for (const std::string& warning : run.warnings) {
      std::cerr << "classify_supervised: warning: " << warning << '\n';
    }
    granular::writeSupervisedJson(options.out, run, classifier);
    run.report(std::cout);
  });
}
