#include "bench_registration.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <granular_core/dataset/models_folder.h>
#include <granular_core/dataset/object_names.h>
#include <granular_core/dataset/pcd_io.h>
#include <granular_core/registration/criteria.h>
#include <granular_core/registration/reference.h>
#include <granular_core/registration/registration_classifier.h>
#include <granular_core/runs/classify_registration_run.h>
#include <pcl/io/pcd_io.h>

#include "granular_ros/presets.h"

namespace granular_ros {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The plain loop's whole run, as a seed-style tool would do it: PCL's generic reader for every
// model (`<label>.pcd`) and object file, the report's loop, then the results JSON (the same
// writer as ours).
granular::ClassificationRun plainWholeRun(const std::filesystem::path& models_folder,
                                          const std::vector<std::string>& model_labels,
                                          const std::filesystem::path& objects_folder,
                                          granular::RegistrationMethod method,
                                          const granular::RegistrationClassifierConfig& config,
                                          const std::filesystem::path& json) {
  const auto readWithPcl = [](const std::filesystem::path& file) {
    granular::ModelCloud cloud;
    if (pcl::io::loadPCDFile(file.string(), cloud) < 0) {
      throw std::runtime_error(file.string() + ": PCL cannot read it");
    }
    return cloud;
  };
  granular::ClassificationRun run;
  run.method = method;
  run.config = config;
  std::vector<granular::LabelledModel> models;
  for (const std::string& label : model_labels) {
    models.push_back({label, readWithPcl(models_folder / (label + ".pcd"))});
  }
  run.models = model_labels;
  std::vector<granular::ModelCloud> objects;
  for (const std::filesystem::path& file : granular::listAllObjectFiles(objects_folder)) {
    objects.push_back(readWithPcl(file));
    granular::ObjectRecord record;
    record.file = file.filename().string();
    record.true_label = granular::objectClass(file);
    record.points = objects.back().size();
    record.points_used = granular::registrationSourceSize(objects.back(), config);
    run.objects.push_back(record);
  }
  const auto results = granular::registerObjectsReference(method, config, models, objects);
  for (std::size_t i = 0; i < results.size(); ++i) {
    run.objects[i].per_model = results[i];
    run.objects[i].predictions = granular::predict(results[i]);
  }
  granular::writeClassificationJson(json, run);
  return run;
}

}  // namespace

void BenchRegistrationOptions::declareIn(Tool& tool) {
  preset = kDefaultPreset;
  tool.describe(
      "usage: bench_registration --models FOLDER --objects FOLDER [options]\n\n"
      "For each method, classifies the objects twice, one run after the other: first as the\n"
      "report's loop did (one thread; for every object and model a fresh PCL registration object\n"
      "given the model as target, so the model's kd-tree, and NDT's voxel grid, are built again\n"
      "for every pair), then as classify_registration does (each model's structures built once,\n"
      "objects spread over threads). Prints the seconds of each, the speed-up, how many objects\n"
      "the two predict differently under the three criteria (different), how many\n"
      "object-model pairs differ at all in state, iterations, fitness or transform (pairs\n"
      "differ), and each loop's criterion-2 accuracy (the objects' labels from their file\n"
      "names). ICP and NDT are bit for bit the report's; ICP-NL's step is an analytic\n"
      "Levenberg-Marquardt that minimises the same sum as PCL's numerical one in float, so its\n"
      "predictions may differ where PCL's stopped short. Needs no roscore.\n",
      "Exit status: 0 done (and ICP's and NDT's predictions agree), 1 failed or they differ,\n"
      "2 bad option, 130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP.\n");
  tool.options()
      .required("--models", models, "FOLDER", "class models (<Class>.pcd)")
      .required("--objects", objects, "FOLDER", "objects (<Class>-<stamp>-<index>.pcd)")
      .list("--methods", methods, "LIST",
            "comma-separated, of icp, icp_nl, ndt (default: all three)")
      .value("--preset", preset, "NAME",
             "parameter preset (default " + std::string(kDefaultPreset) + ")")
      .value("--config", config_file, "FILE",
             "YAML file with presets (config/classification.yaml)")
      .threads("--threads", threads, "threads of the fast run (default: every core)")
      .flag("--early-rejection", early_rejection,
            "the fast run skips the fitness of the models that cannot decide a prediction "
            "(classify_registration --early-rejection); those pairs are counted as rejected, "
            "and compared in all but the fitness")
      .value("--end-to-end", end_to_end, "DIR",
             "time whole runs instead, from reading the files to the results JSON written into "
             "DIR (created; METHOD_granular.json and METHOD_plain_loop.json replaced for each "
             "method): granular's as classify_registration runs (classifyFolder, then "
             "writeClassificationJson), against the plain loop's whole run (every object and "
             "model read with PCL's pcl::io::loadPCDFile, the report's loop, the same JSON "
             "written)");
}

bool compareWholeRuns(const BenchRegistrationOptions& options,
                      const granular::RegistrationClassifierConfig& config) {
  const std::filesystem::path out = *options.end_to_end;
  std::filesystem::create_directories(out);
  std::printf("whole runs, reading the files to the JSON written (into %s), preset %s\n",
              out.c_str(), options.preset.c_str());
  std::printf("%-8s %10s %16s %16s %9s %12s\n", "method", "objects", "plain loop, whole",
              "granular, whole", "speed-up", "different");
  bool agree = true;
  for (const std::string& name : options.methods) {
    const granular::RegistrationMethod method = *granular::registrationMethodFromName(name);
    granular::ClassifyFolderOptions fast_options;
    fast_options.preset = options.preset;
    fast_options.registration.threads = options.threads;
    fast_options.registration.early_rejection = options.early_rejection;
    auto start = std::chrono::steady_clock::now();
    const granular::ClassificationRun fast =
        granular::classifyFolder(options.models, options.objects, method, config, fast_options);
    granular::writeClassificationJson(out / (name + "_granular.json"), fast);
    const double fast_seconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    // The model labels granular's run found: the plain run reads their files, not the folder.
    const granular::ClassificationRun plain =
        plainWholeRun(options.models, fast.models, options.objects, method, config,
                      out / (name + "_plain_loop.json"));
    const double plain_seconds = secondsSince(start);

    std::vector<std::vector<granular::PairResult>> fast_pairs, plain_pairs;
    for (std::size_t i = 0; i < fast.objects.size(); ++i) {
      fast_pairs.push_back(fast.objects[i].per_model);
      plain_pairs.push_back(plain.objects[i].per_model);
    }
    const std::size_t different =
        granular::compareWithReference(plain_pairs, fast_pairs).different_predictions;
    agree = agree && (different == 0 || method == granular::RegistrationMethod::kIcpNl);
    std::printf("%-8s %10zu %15.2fs %15.3fs %8.1fx %12zu\n", name.c_str(), fast.objects.size(),
                plain_seconds, fast_seconds, plain_seconds / fast_seconds, different);
    std::fflush(stdout);
  }
  return agree;
}

bool compareLoops(const BenchRegistrationOptions& options,
                  const granular::RegistrationClassifierConfig& config) {
  const std::vector<granular::LabelledModel> models = granular::readClassModels(options.models);
  std::vector<granular::ModelCloud> objects;
  std::vector<std::string> labels;
  for (const std::filesystem::path& file : granular::listAllObjectFiles(options.objects)) {
    objects.push_back(granular::readModelPcd(file));
    labels.push_back(granular::objectClass(file));
  }
  std::printf("%zu objects, %zu models, preset %s\n", objects.size(), models.size(),
              options.preset.c_str());
  std::printf("%-8s %12s %12s %10s %9s %12s %14s %10s %13s %13s\n", "method", "report loop",
              "granular", "speed-up", "threads", "different", "pairs differ", "rejected",
              "accuracy loop", "accuracy ours");
  bool agree = true;
  for (const std::string& name : options.methods) {
    const granular::RegistrationMethod method = *granular::registrationMethodFromName(name);
    granular::RegisterOptions fast_options;
    fast_options.threads = options.threads;
    fast_options.early_rejection = options.early_rejection;

    // The classifier's constructor builds the models' structures: part of our time.
    auto start = std::chrono::steady_clock::now();
    const granular::RegistrationClassifier classifier(method, config, models);
    const auto fast = classifier.registerObjects(objects, fast_options);
    const double fast_seconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    const auto plain = granular::registerObjectsReference(method, config, models, objects);
    const double plain_seconds = secondsSince(start);

    const granular::ReferenceComparison comparison = granular::compareWithReference(plain, fast);
    const bool exact = method != granular::RegistrationMethod::kIcpNl;
    agree = agree && (comparison.different_predictions == 0 || !exact);
    std::printf("%-8s %11.2fs %11.3fs %9.1fx %9d %12zu %14zu %10zu %13.3f %13.3f\n",
                name.c_str(), plain_seconds, fast_seconds, plain_seconds / fast_seconds,
                granular::registrationThreads(fast_options), comparison.different_predictions,
                comparison.different_pairs, comparison.rejected_pairs,
                granular::criterion2Accuracy(plain, labels, models),
                granular::criterion2Accuracy(fast, labels, models));
    std::fflush(stdout);
  }
  return agree;
}

}  // namespace granular_ros
