// classify_supervised: a train_classifier model's predictions for an objects folder (or, for
// svm_fitness, registration results), one JSON record per object.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <granular_core/dataset/atomic_file.h>
#include <granular_core/runs/classify_supervised_run.h>

#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

int main(int argc, char** argv) {
  std::string model, objects, registration, out;
  std::optional<std::string> config_file;
  int threads = 0;
  granular_ros::Tool tool(
      "classify_supervised",
      "usage: classify_supervised --model MODEL.yml --objects FOLDER --out FILE.json [options]\n"
      "       classify_supervised --model MODEL.yml --registration FILE.json[,FILE.json...]\n"
      "                           [--objects FOLDER] --out FILE.json [options]\n\n"
      "Classifies each object PCD of an objects folder (<Class>-<stamp>-<index>.pcd, object\n"
      "frame) with a classifier written by train_classifier, computing the features with the\n"
      "settings stored in the model. An svm_fitness model classifies the objects of\n"
      "classify_registration results instead (--registration: the same methods, presets and\n"
      "models, in the order it was trained with), with the objects' point histograms from\n"
      "--objects when it was trained on them. Writes FILE.json: per object its true label\n"
      "(from the name) and the prediction; the wall time and the microseconds per object\n"
      "(features and prediction, on one core). Needs no roscore.\n",
      "Exit status: 0 done, 1 failed (unreadable model, folder or results, results registered\n"
      "otherwise than the model's, output not writable), 2 bad option, configuration, a model of\n"
      "other feature settings than --config, or --objects and --registration mixed up;\n"
      "130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP.\n");
  tool.options()
      .required("--model", model, "MODEL.yml", "classifier to use")
      .value("--objects", objects, "FOLDER",
             "objects to classify (knn, svm, svm_esf; svm_fitness: those its --registration "
             "results are of, for its point histograms)")
      .value("--registration", registration, "FILE.json[,FILE.json...]",
             "svm_fitness: classify_registration results of the objects to classify")
      .required("--out", out, "FILE.json", "results file to write (replaced)")
      .value("--config", config_file, "FILE",
             "YAML file with the feature settings you expect (config/supervised.yaml); a model "
             "trained with other settings is refused")
      .threads("--threads", threads, "threads (default: every core)");
  std::optional<granular::SupervisedConfig> expected;
  const auto configure = [&] {
    if (objects.empty() && registration.empty()) {
      throw granular_ros::UsageError(
          "give --objects (knn, svm, svm_esf) or --registration (svm_fitness)");
    }
    if (config_file) {
      expected = granular_ros::buildConfig<granular::SupervisedConfig>(config_file);
    }
  };
  return tool.run(argc, argv, configure, [&] {
    granular::checkCanWrite(out, "JSON");  // before the work, not after it
    const auto classifier = granular::SupervisedClassifier::load(model);
    granular_ros::refuseIfProblem(granular::supervisedInputsProblem(
        classifier, model, expected ? &*expected : nullptr, config_file.value_or(""),
        !objects.empty(), !registration.empty()));
    const std::vector<std::string> files =
        registration.empty() ? std::vector<std::string>{}
                             : granular_ros::splitList("--registration", registration);
    const granular::SupervisedRun run =
        files.empty() ? granular::classifyFolderSupervised(
                            classifier, objects, threads,
                            tool.progress(granular::supervisedMethodName(classifier.method()),
                                          "objects"))
                      : granular::classifyRegistrationResults(
                            classifier, {files.begin(), files.end()}, objects, threads);
    tool.warn(run.warnings);
    granular::writeSupervisedJson(out, run, classifier);
    run.report(std::cout);
  });
}
