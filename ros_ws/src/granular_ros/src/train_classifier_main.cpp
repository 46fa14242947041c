// train_classifier: the command-line face of granular::trainOnFolder and trainOnRegistration.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <granular_core/runs/classify_supervised_run.h>

#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

int main(int argc, char** argv) {
  std::string objects, method_name, out;
  std::vector<std::string> registration, classes;
  std::optional<std::string> config_file;
  std::optional<std::size_t> search_objects;
  int threads = 0;
  granular_ros::Tool tool(
      "train_classifier",
      "usage: train_classifier --objects FOLDER --method METHOD --out MODEL.yml [options]\n"
      "       train_classifier --registration FILE.json[,FILE.json...] --method svm_fitness\n"
      "                        --objects FOLDER --out MODEL.yml [options]\n\n"
      "Trains a supervised classifier on the object PCDs of a training objects folder\n"
      "(<Class>-<stamp>-<index>.pcd, object frame; the class comes from the name) and writes it,\n"
      "with the feature settings it was trained with, to MODEL.yml. Needs no roscore.\n",
      "Exit status: 0 trained, 1 failed (unreadable or empty folder or results, a single class,\n"
      "output not writable), 2 bad option or configuration, 130/143/129 interrupted by\n"
      "SIGINT/SIGTERM/SIGHUP.\n");
  tool.options()
      .value("--objects", objects, "FOLDER",
             "training objects (knn, svm, svm_esf; svm_fitness: those its --registration "
             "results are of)")
      .list("--registration", registration, "FILE.json[,FILE.json...]",
             "svm_fitness: classify_registration results of the training objects; classify "
             "later with results of the same methods, presets and models, in the same order")
      .required("--method", method_name, "METHOD",
                "knn: k nearest neighbours on [mean, std] of x, y, z (report 8.4)\nsvm: nu-SVM, "
                "RBF kernel, on 60 point-feature-histogram values (paper 001); nu and gamma by a "
                "cross-validated grid search on these objects only\nsvm_esf: the same nu-SVM on "
                "PCL's 640 ESF values\nsvm_fitness: the same nu-SVM on each object's fitness "
                "against every class model (log) and its point count, from "
                "classify_registration's results on the training objects (--registration, one "
                "file per method, e.g. ICP, NDT and ICP-NL with the tuned preset, as "
                "run_evaluation trains it), and on the objects' point-feature histograms, "
                "weighted by svm_fitness.histogram_weight (0: the results alone, no --objects "
                "needed)")
      .required("--out", out, "MODEL.yml", "model file to write (replaced)")
      .list("--classes", classes, "LIST",
             "train on the objects of these classes only, comma-separated, e.g. the classes "
             "that have models (default: every class)")
      .value("--config", config_file, "FILE",
             "YAML file with knn, svm, svm_fitness and histograms (the repository's "
             "config/supervised.yaml documents them)")
      .number("--search-objects", search_objects, "N",
              "svm methods: cross-validate the grid search on a stratified sample of about N "
              "objects (0: all; each class's share rounded, and every class keeps enough for "
              "the folds), then train the chosen nu and gamma on all; overrides "
              "svm.search_objects of --config")
      .threads("--threads", threads, "threads for the features (default: every core)");
  granular::SupervisedConfig config;
  granular::SupervisedMethod method{};
  const auto configure = [&] {
    method = granular_ros::parseChoice<granular::SupervisedMethod>("--method", method_name);
    config = granular_ros::buildConfig<granular::SupervisedConfig>(config_file);
    config.svm.search_objects = search_objects.value_or(config.svm.search_objects);
    granular_ros::refuseIfProblem(granular::trainingInputsProblem(
        method, config, !objects.empty(), !registration.empty()));
  };
  return tool.run(argc, argv, configure, [&] {
    const granular::TrainingRun run =
        registration.empty()
            ? granular::trainOnFolder(objects, method, config, threads,
                                      tool.progress("features", "objects"), classes)
            : granular::trainOnRegistration({registration.begin(), registration.end()}, config,
                                            objects, threads, classes);
    run.classifier.save(out);
    run.report(std::cout);
    std::cout << "model: " << out << '\n';
  });
}
