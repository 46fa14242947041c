// train_classifier: computes the features of a training objects folder and trains a kNN or a
// nu-SVM classifier on them; writes the model file classify_supervised and the online node load.
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
    "usage: train_classifier --objects FOLDER --method METHOD --out MODEL.yml [options]\n"
    "\n"
    "Trains a supervised classifier on the object PCDs of a training objects folder\n"
    "(<Class>-<stamp>-<index>.pcd, object frame; the class comes from the name) and writes it,\n"
    "with the feature settings it was trained with, to MODEL.yml. Needs no roscore.\n"
    "\n"
    "methods:\n"
    "  knn      k nearest neighbours on [mean, std] of x, y, z (report 8.4)\n"
    "  svm      nu-SVM, RBF kernel, on 60 point-feature-histogram values (paper 001); nu and\n"
    "           gamma by a cross-validated grid search on these objects only\n"
    "  svm_esf  the same nu-SVM on PCL's 640 ESF values\n"
    "\n"
    "options:\n"
    "  --objects FOLDER  training objects\n"
    "  --method METHOD   knn, svm or svm_esf\n"
    "  --out MODEL.yml   model file to write (replaced)\n"
    "  --config FILE     YAML file with knn, svm and histograms (the repository's\n"
    "                    config/supervised.yaml documents them)\n"
    "  --threads N       threads for the features (default: every core)\n"
    "  --help            print this help and exit\n"
    "\n"
    "Exit status: 0 trained, 1 failed (unreadable or empty folder, a single class, output not\n"
    "writable), 2 bad option or configuration.\n";

struct Options {
  std::string objects;
  std::string method;
  std::string out;
  std::optional<std::string> config_file;
  int threads = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::SupervisedConfig config;
  granular::SupervisedMethod method{};
  granular_ros::Tool tool("train_classifier", [] { return std::string(kUsage); });
  tool.options()
      .required("--objects", options.objects)
      .required("--method", options.method)
      .required("--out", options.out)
      .value("--config", options.config_file)
      .threads("--threads", options.threads);
  const auto configure = [&] {
    const auto parsed = granular::supervisedMethodFromName(options.method);
    if (!parsed) {
      throw std::invalid_argument("--method: expected knn, svm or svm_esf, got '" +
                                  options.method + "'");
    }
    method = *parsed;
    config = granular_ros::buildConfig<granular::SupervisedConfig>(options.config_file);
  };
  return tool.run(argc, argv, configure, [&] {
    const granular::TrainingRun run = granular::trainOnFolder(
        options.objects, method, config, options.threads, tool.progress("features", "objects"));
    run.classifier.save(options.out);
    run.report(std::cout);
    std::cout << "model: " << options.out << '\n';
  });
}
