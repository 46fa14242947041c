// bench_registration: the report's registration loop against granular's, on the same objects
// and models in one process, one after the other. Prints seconds and the speed-up per method,
// and whether both give the same predictions.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/dataset/models_folder.h>
#include <granular_core/dataset/object_names.h>
#include <granular_core/dataset/pcd_io.h>
#include <granular_core/registration/criteria.h>
#include <granular_core/registration/reference.h>
#include <granular_core/registration/registration.h>
#include <granular_core/registration/registration_classifier.h>
#include <granular_core/runs/classify_registration_run.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include "granular_ros/presets.h"
#include "granular_ros/command_line.h"
#include "granular_ros/tool.h"

namespace {

const char* const kUsage =
    "usage: bench_registration --models FOLDER --objects FOLDER [options]\n"
    "\n"
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
    "predictions may differ where PCL's stopped short. Needs no roscore.\n"
    "\n"
    "options:\n"
    "  --models FOLDER    class models (<Class>.pcd)\n"
    "  --objects FOLDER   objects (<Class>-<stamp>-<index>.pcd)\n"
    "  --methods LIST     comma-separated, of icp, icp_nl, ndt (default: all three)\n"
    "  --preset NAME      parameter preset (default tuned)\n"
    "  --config FILE      YAML file with presets (config/classification.yaml)\n"
    "  --threads N        threads of the fast run (default: every core)\n"
    "  --early-rejection  the fast run skips the fitness of the models that cannot decide a\n"
    "                     prediction (classify_registration --early-rejection); those pairs\n"
    "                     are counted as rejected, and compared in all but the fitness\n"
    "  --end-to-end DIR   time whole runs instead, from reading the files to the results\n"
    "                     JSON written into DIR (created; METHOD_granular.json and\n"
    "                     METHOD_plain_loop.json replaced for each method):\n"
    "                     granular's as classify_registration runs (classifyFolder, then\n"
    "                     writeClassificationJson), against the plain loop's whole run\n"
    "                     (every object and model read with PCL's pcl::io::loadPCDFile, the\n"
    "                     report's loop, the same JSON written)\n"
    "  -h, --help         print this help and exit\n"
    "\n"
    "Exit status: 0 done (and ICP's and NDT's predictions agree), 1 failed or they differ,\n"
    "2 bad option, 130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP.\n";

struct Options {
  std::string models;
  std::string objects;
  std::vector<std::string> methods = {"icp", "icp_nl", "ndt"};
  std::string preset = granular_ros::kDefaultPreset;
  std::optional<std::string> config_file;
  int threads = 0;
  std::optional<std::string> end_to_end;  ///< folder for the whole runs' JSON files
  bool early_rejection = false;
};

struct Objects {
  std::vector<granular::ModelCloud> clouds;
  std::vector<std::string> labels;
};

Objects readObjects(const std::filesystem::path& folder) {
  Objects objects;
  for (const std::filesystem::path& file : granular::listAllObjectFiles(folder)) {
    objects.clouds.push_back(granular::readModelPcd(file));
    objects.labels.push_back(granular::objectClass(file));
  }
  return objects;
}

// Share of the objects whose criterion-2 prediction is their label (none counts as wrong).
double criterion2Accuracy(const std::vector<std::vector<granular::PairResult>>& results,
                          const std::vector<std::string>& labels,
                          const std::vector<granular::LabelledModel>& models) {
  std::size_t correct = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::optional<std::size_t> predicted = granular::predict(results[i]).criterion2;
    correct += predicted && models[*predicted].label == labels[i];
  }
  return results.empty() ? 0.0 : static_cast<double>(correct) / results.size();
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Objects whose predictions differ under any criterion.
std::size_t differentPredictions(const std::vector<std::vector<granular::PairResult>>& a,
                                 const std::vector<std::vector<granular::PairResult>>& b) {
  std::size_t different = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const granular::Predictions pa = granular::predict(a[i]);
    const granular::Predictions pb = granular::predict(b[i]);
    for (int criterion = 1; criterion <= 3; ++criterion) {
      if (pa.criterion(criterion) != pb.criterion(criterion)) {
        ++different;
        break;
      }
    }
  }
  return different;
}

// Pairs of `b` whose fitness was rejected early.
std::size_t rejectedPairs(const std::vector<std::vector<granular::PairResult>>& b) {
  std::size_t rejected = 0;
  for (const auto& per_model : b) {
    rejected += std::count_if(per_model.begin(), per_model.end(),
                              [](const granular::PairResult& pair) { return pair.rejected; });
  }
  return rejected;
}

// Pairs whose state, iterations, fitness (unless `b`'s was rejected) or transform differ.
std::size_t differentPairs(const std::vector<std::vector<granular::PairResult>>& a,
                           const std::vector<std::vector<granular::PairResult>>& b) {
  std::size_t different = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t m = 0; m < a[i].size(); ++m) {
      const granular::PairResult& pa = a[i][m];
      const granular::PairResult& pb = b[i][m];
      const bool same_fitness = pb.rejected || pa.fitness == pb.fitness ||
                                (std::isnan(pa.fitness) && std::isnan(pb.fitness));
      if (pa.state != pb.state || pa.iterations != pb.iterations || !same_fitness ||
          pa.transform != pb.transform) {
        ++different;
      }
    }
  }
  return different;
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

// --end-to-end: each method's whole run, ours then the plain loop's, and their ratio. False
// when ICP's or NDT's predictions differ between the two (they must not: both are exact).
bool endToEnd(const Options& options, const granular::RegistrationClassifierConfig& config) {
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
    const std::size_t different = differentPredictions(plain_pairs, fast_pairs);
    agree = agree && (different == 0 || method == granular::RegistrationMethod::kIcpNl);
    std::printf("%-8s %10zu %15.2fs %15.3fs %8.1fx %12zu\n", name.c_str(), fast.objects.size(),
                plain_seconds, fast_seconds, plain_seconds / fast_seconds, different);
    std::fflush(stdout);
  }
  return agree;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::RegistrationClassifierConfig config;
  granular_ros::Tool tool("bench_registration", [] { return std::string(kUsage); });
  tool.options()
      .required("--models", options.models)
      .required("--objects", options.objects)
      .custom("--methods",
              [&options](granular_ros::OptionReader& reader) {
                options.methods = granular_ros::splitList("--methods", reader.value());
              })
      .value("--preset", options.preset)
      .value("--config", options.config_file)
      .threads("--threads", options.threads)
      .value("--end-to-end", options.end_to_end)
      .flag("--early-rejection", options.early_rejection);
  const auto configure = [&] {
    config = granular_ros::resolvePreset(options.config_file, options.preset);
    for (const std::string& method : options.methods) {
      if (!granular::registrationMethodFromName(method)) {
        throw std::invalid_argument("--methods: unknown method '" + method + "'");
      }
    }
  };
  return tool.run(argc, argv, configure, [&] {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    if (options.end_to_end) {
      if (!endToEnd(options, config)) {
        throw std::runtime_error("the two whole runs predict differently (ICP or NDT)");
      }
      return;
    }
    const std::vector<granular::LabelledModel> models = granular::readClassModels(options.models);
    const Objects read = readObjects(options.objects);
    const std::vector<granular::ModelCloud>& objects = read.clouds;
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

      const std::size_t different = differentPredictions(plain, fast);
      const bool exact = method != granular::RegistrationMethod::kIcpNl;
      agree = agree && (different == 0 || !exact);
      const int threads = granular::registrationThreads(fast_options);
      std::printf("%-8s %11.2fs %11.3fs %9.1fx %9d %12zu %14zu %10zu %13.3f %13.3f\n",
                  name.c_str(), plain_seconds, fast_seconds, plain_seconds / fast_seconds,
                  threads, different, differentPairs(plain, fast), rejectedPairs(fast),
                  criterion2Accuracy(plain, read.labels, models),
                  criterion2Accuracy(fast, read.labels, models));
      std::fflush(stdout);
    }
    if (!agree) {
      throw std::runtime_error("the two loops predict differently (ICP or NDT)");
    }
  });
}
