// train_classifier: computes the features of a training objects folder (or reads the
// registration results of one) and trains a kNN or a nu-SVM classifier on them; writes the model
// file classify_supervised and the online node load.
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/runs/classify_supervised_run.h>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

const char* const kUsage =
    "usage: train_classifier --objects FOLDER --method METHOD --out MODEL.yml [options]\n"
    "       train_classifier --registration FILE.json[,FILE.json...] --method svm_fitness\n"
    "                        --objects FOLDER --out MODEL.yml [options]\n"
    "\n"
    "Trains a supervised classifier on the object PCDs of a training objects folder\n"
    "(<Class>-<stamp>-<index>.pcd, object frame; the class comes from the name) and writes it,\n"
    "with the feature settings it was trained with, to MODEL.yml. Needs no roscore.\n"
    "\n"
    "methods:\n"
    "  knn          k nearest neighbours on [mean, std] of x, y, z (report 8.4)\n"
    "  svm          nu-SVM, RBF kernel, on 60 point-feature-histogram values (paper 001); nu\n"
    "               and gamma by a cross-validated grid search on these objects only\n"
    "  svm_esf      the same nu-SVM on PCL's 640 ESF values\n"
    "  svm_fitness  the same nu-SVM on each object's fitness against every class model (log)\n"
    "               and its point count, from classify_registration's results on the\n"
    "               training objects (--registration, one file per method, e.g. ICP, NDT\n"
    "               and ICP-NL with the tuned preset, as run_evaluation trains it), and on\n"
    "               the objects' point-feature histograms, weighted by\n"
    "               svm_fitness.histogram_weight (0: the results alone, no --objects needed)\n"
    "\n"
    "options:\n"
    "  --objects FOLDER  training objects (knn, svm, svm_esf; svm_fitness: those its\n"
    "                    --registration results are of)\n"
    "  --registration FILE.json[,FILE.json...]\n"
    "                    svm_fitness: classify_registration results of the training objects;\n"
    "                    classify later with results of the same methods, presets and models,\n"
    "                    in the same order\n"
    "  --method METHOD   knn, svm, svm_esf or svm_fitness\n"
    "  --out MODEL.yml   model file to write (replaced)\n"
    "  --classes LIST    train on the objects of these classes only, comma-separated, e.g.\n"
    "                    the classes that have models (default: every class)\n"
    "  --config FILE     YAML file with knn, svm, svm_fitness and histograms (the repository's\n"
    "                    config/supervised.yaml documents them)\n"
    "  --search-objects N\n"
    "                    svm methods: cross-validate the grid search on a stratified sample\n"
    "                    of about N objects (0: all; each class's share rounded, and every\n"
    "                    class keeps enough for the folds), then train the chosen nu and\n"
    "                    gamma on all; overrides svm.search_objects of --config\n"
    "  --threads N       threads for the features (default: every core)\n"
    "  -h, --help        print this help and exit\n"
    "\n"
    "Exit status: 0 trained, 1 failed (unreadable or empty folder or results, a single class,\n"
    "output not writable), 2 bad option or configuration, 130/143/129 interrupted by\n"
    "SIGINT/SIGTERM/SIGHUP.\n";

struct Options {
  std::string objects;
  std::string registration;
  std::string method;
  std::string out;
  std::optional<std::string> config_file;
  std::optional<std::string> classes;
  int threads = 0;
  std::optional<std::size_t> search_objects;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::SupervisedConfig config;
  granular::SupervisedMethod method{};
  std::vector<std::filesystem::path> registration;
  std::vector<std::string> classes;
  granular_ros::Tool tool("train_classifier", [] { return std::string(kUsage); });
  tool.options()
      .value("--objects", options.objects)
      .value("--registration", options.registration)
      .required("--method", options.method)
      .required("--out", options.out)
      .value("--config", options.config_file)
      .value("--classes", options.classes)
      .custom("--search-objects",
              [&options](granular_ros::OptionReader& reader) {
                options.search_objects =
                    granular_ros::parseNumber<std::size_t>("--search-objects", reader.value());
              })
      .threads("--threads", options.threads);
  const auto configure = [&] {
    const auto parsed = granular::supervisedMethodFromName(options.method);
    if (!parsed) {
      throw std::invalid_argument("--method: expected knn, svm, svm_esf or svm_fitness, got '" +
                                  options.method + "'");
    }
    method = *parsed;
    const bool from_registration = method == granular::SupervisedMethod::kSvmFitness;
    if (from_registration && options.registration.empty()) {
      throw granular_ros::UsageError(
          "--method svm_fitness learns from --registration results files (and the --objects "
          "they are of)");
    }
    if (!from_registration && (options.objects.empty() || !options.registration.empty())) {
      throw granular_ros::UsageError("--method " + options.method +
                                     " needs --objects (only svm_fitness takes --registration)");
    }
    if (from_registration) {
      const std::vector<std::string> files =
          granular_ros::splitList("--registration", options.registration);
      registration.assign(files.begin(), files.end());
    }
    if (options.classes) {
      classes = granular_ros::splitList("--classes", *options.classes);
    }
    config = granular_ros::buildConfig<granular::SupervisedConfig>(options.config_file);
    if (options.search_objects) {
      config.svm.search_objects = *options.search_objects;
    }
    if (from_registration && config.svm_fitness.histogram_weight > 0.0 && options.objects.empty()) {
      throw granular_ros::UsageError(
          "--method svm_fitness also learns the objects' point histograms: give --objects, the "
          "folder the --registration results are of (or svm_fitness.histogram_weight: 0)");
    }
  };
  return tool.run(argc, argv, configure, [&] {
    const granular::TrainingRun run =
        options.registration.empty()
            ? granular::trainOnFolder(options.objects, method, config, options.threads,
                                      tool.progress("features", "objects"), classes)
            : granular::trainOnRegistration(registration, config, options.objects,
                                            options.threads, classes);
    run.classifier.save(options.out);
    run.report(std::cout);
    std::cout << "model: " << options.out << '\n';
  });
}
