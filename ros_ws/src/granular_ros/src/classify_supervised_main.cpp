// classify_supervised: classifies every object of an objects folder (or of registration results,
// for svm_fitness) with a model written by train_classifier and writes one JSON record per
// object.
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/dataset/atomic_file.h>
#include <granular_core/runs/classify_supervised_run.h>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

const char* const kUsage =
    "usage: classify_supervised --model MODEL.yml --objects FOLDER --out FILE.json [options]\n"
    "       classify_supervised --model MODEL.yml --registration FILE.json[,FILE.json...]\n"
    "                           [--objects FOLDER] --out FILE.json [options]\n"
    "\n"
    "Classifies each object PCD of an objects folder (<Class>-<stamp>-<index>.pcd, object\n"
    "frame) with a classifier written by train_classifier, computing the features with the\n"
    "settings stored in the model. An svm_fitness model classifies the objects of\n"
    "classify_registration results instead (--registration: the same methods, presets and\n"
    "models, in the order it was trained with), with the objects' point histograms from\n"
    "--objects when it was trained on them. Writes FILE.json: per object its true label\n"
    "(from the name) and the prediction; the wall time and the microseconds per object\n"
    "(features and prediction, on one core). Needs no roscore.\n"
    "\n"
    "options:\n"
    "  --model MODEL.yml  classifier to use\n"
    "  --objects FOLDER   objects to classify (knn, svm, svm_esf; svm_fitness: those its\n"
    "                     --registration results are of, for its point histograms)\n"
    "  --registration FILE.json[,FILE.json...]\n"
    "                     svm_fitness: classify_registration results of the objects to classify\n"
    "  --out FILE.json    results file to write (replaced)\n"
    "  --config FILE      YAML file with the feature settings you expect (config/\n"
    "                     supervised.yaml); a model trained with other settings is refused\n"
    "  --threads N        threads (default: every core)\n"
    "  -h, --help         print this help and exit\n"
    "\n"
    "Exit status: 0 done, 1 failed (unreadable model, folder or results, results registered\n"
    "otherwise than the model's, output not writable), 2 bad option, configuration, a model of\n"
    "other feature settings than --config, or --objects and --registration mixed up;\n"
    "130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP.\n";

struct Options {
  std::string model;
  std::string objects;
  std::string registration;
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
      .value("--objects", options.objects)
      .value("--registration", options.registration)
      .required("--out", options.out)
      .value("--config", options.config_file)
      .threads("--threads", options.threads);
  const auto configure = [&] {
    if (options.objects.empty() && options.registration.empty()) {
      throw granular_ros::UsageError(
          "give --objects (knn, svm, svm_esf) or --registration (svm_fitness)");
    }
    if (options.config_file) {
      expected = granular_ros::buildConfig<granular::SupervisedConfig>(options.config_file);
    }
  };
  return tool.run(argc, argv, configure, [&] {
    granular::checkCanWrite(options.out, "JSON");  // before the work, not after it
    const granular::SupervisedClassifier classifier =
        granular::SupervisedClassifier::load(options.model);
    if (expected) {
      // svm_fitness's point histograms, when it takes them, are computed as the svm's.
      const std::string difference = granular::featureConfigDifference(
          classifier.takesPointHistograms() ? granular::SupervisedMethod::kSvm
                                            : classifier.method(),
          classifier.config().histograms, expected->histograms);
      if (!difference.empty()) {
        throw granular_ros::UsageError(
            options.model + " was trained with other feature settings than " +
            *options.config_file + " (histograms." + difference +
            "); retrain it, or leave --config out to use the model's own");
      }
    }
    const std::string method = granular::supervisedMethodName(classifier.method());
    const bool from_registration =
        classifier.method() == granular::SupervisedMethod::kSvmFitness;
    if (from_registration == options.registration.empty()) {
      throw granular_ros::UsageError(
          options.model + " is a " + method + " classifier: give it " +
          (from_registration ? "--registration results files" : "--objects, not --registration"));
    }
    if (from_registration && classifier.takesPointHistograms() && options.objects.empty()) {
      throw granular_ros::UsageError(
          options.model + " also takes the objects' point histograms: give --objects, the "
          "folder its --registration results are of");
    }
    granular::SupervisedRun run;
    if (from_registration) {
      const std::vector<std::string> files =
          granular_ros::splitList("--registration", options.registration);
      run = granular::classifyRegistrationResults(
          classifier, std::vector<std::filesystem::path>(files.begin(), files.end()),
          options.objects, options.threads);
    } else {
      run = granular::classifyFolderSupervised(classifier, options.objects, options.threads,
                                               tool.progress(method, "objects"));
    }
    for (const std::string& warning : run.warnings) {
      std::cerr << "classify_supervised: warning: " << warning << '\n';
    }
    granular::writeSupervisedJson(options.out, run, classifier);
    run.report(std::cout);
  });
}
