// build_models: the command-line face of granular::buildModels. Reads options and an optional
// YAML config, builds one model per class, reports progress on stderr and a table on stdout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/models/build_models.h>

#include "granular_ros/command_line.h"
#include "granular_ros/model_config_yaml.h"
#include "granular_ros/tool.h"

namespace {

std::string usage() {
  const granular::ModelBuildConfig defaults;
  const granular::FilterChainConfig& chain = defaults.filters;
  std::ostringstream stages;
  for (const granular::FilterStage stage : chain.order) {
    stages << (stages.tellp() > 0 ? ", " : "") << granular::stageName(stage);
  }
  std::ostringstream text;
  text << "usage: build_models --objects FOLDER --out FOLDER [options]\n"
          "\n"
          "Stacks the object PCDs of each class of an objects folder (<Class>-<stamp>-<index>\n"
          ".pcd, as extract_objects writes them) into one model per class and filters it (report\n"
          "sections 5.2 and 5.3). Writes OUT/<Class>.pcd (filtered, fields x y z), OUT/raw/\n"
          "<Class>.pcd (concatenated), OUT/models.json (objects used and kept, points after each\n"
          "stage, parameters) and, with --mesh, OUT/mesh/<Class>.ply. Needs no roscore.\n"
          "\n"
          "options:\n"
          "  --objects FOLDER     objects folder to read\n"
          "  --out FOLDER         models folder to create\n"
          "  --method plain|icp   plain concatenation, or each object aligned to the growing\n"
          "                       model with ICP and kept if it converged with a good fit\n"
          "                       (default "
       << granular::methodName(defaults.method)
       << ")\n"
          "  --seed CLASS=FILE    ICP seed model of CLASS (a PCD in the object frame); repeat\n"
          "                       for several classes. Default: the objects with most points\n"
          "                       showing each side (front, back, left, right)\n"
          "  --classes LIST       classes to build, comma-separated, e.g. Sedan,SUV (default:\n"
          "                       every class in the folder)\n"
          "  --config FILE        YAML file with method, seed, icp, filters, class_filters and\n"
          "                       mesh (the repository's config/models.yaml documents them);\n"
          "                       options above override it\n"
          "  --mesh               also write a triangle mesh of each model\n"
          "  --overwrite          replace --out when a granular tool wrote it (a folder of other\n"
          "                       files is never replaced)\n"
          "  --help               print this help and exit\n"
          "\n"
          "Default filter chain: "
       << stages.str() << " (pass-through z " << chain.pass_through.min_z << "-"
       << chain.pass_through.max_z << " m, radius " << chain.radius_outlier.radius << " m with "
       << chain.radius_outlier.min_neighbors << " neighbours, K = "
       << chain.statistical_outlier.mean_k << ", m = " << chain.statistical_outlier.stddev_mul
       << ", leaf " << chain.voxel_grid.leaf_size
       << " m), with per-class overrides.\n"
          "\n"
          "Progress goes to stderr, the summary table to stdout. --out is built beside itself\n"
          "and put in place when complete; a second run into it is refused meanwhile. Exit\n"
          "status: 0 done, 1 failed (unreadable input, no objects, output not writable or\n"
          "holding results without --overwrite), 2 bad option or configuration, 130/143\n"
          "interrupted (nothing left half written).\n";
  return text.str();
}

struct Options {
  std::string objects;
  std::string out;
  std::optional<std::string> config_file;
  std::optional<std::string> method;
  std::optional<std::string> classes;
  std::map<std::string, std::filesystem::path> seeds;
  bool mesh = false;
  bool overwrite = false;
};

void declareOptions(granular_ros::OptionTable& table, Options& options) {
  table.flag("--overwrite", options.overwrite)
      .flag("--mesh", options.mesh)
      .required("--objects", options.objects)
      .required("--out", options.out)
      .value("--config", options.config_file)
      .value("--method", options.method)
      .value("--classes", options.classes)
      .custom("--seed",
              [&options](granular_ros::OptionReader& reader) {
                const std::string seed = reader.value();
                const auto separator = seed.find('=');
                if (separator == 0 || separator == std::string::npos ||
                    separator + 1 == seed.size()) {
                  throw std::invalid_argument("--seed: expected CLASS=FILE.pcd, got '" + seed +
                                              "'");
                }
                const std::string label = seed.substr(0, separator);
                if (!options.seeds.emplace(label, seed.substr(separator + 1)).second) {
                  throw std::invalid_argument("--seed: class '" + label + "' given twice");
                }
              });
}

// Defaults, then the YAML file, then the command line.
granular::ModelBuildConfig buildConfig(const Options& options) {
  granular::ModelBuildConfig config;
  if (options.config_file) {
    granular_ros::loadModelConfig(*options.config_file, config);
  }
  if (options.method) {
    const auto method = granular::methodFromName(*options.method);
    if (!method) {
      throw std::invalid_argument("--method: expected plain or icp, got '" + *options.method +
                                  "'");
    }
    config.method = *method;
  }
  try {
    granular::validate(config);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("invalid configuration: ") + error.what());
  }
  return config;
}

void reportClass(const granular::ClassModelSummary& summary) {
  std::fprintf(stderr, "%s: %zu objects, %zu kept, %zu raw points, %zu model points, %.2f s\n",
               summary.label.c_str(), summary.objects, summary.kept, summary.raw_points,
               summary.points, summary.seconds);
  for (const std::string& warning : summary.warnings) {
    std::fprintf(stderr, "%s: warning: %s\n", summary.label.c_str(), warning.c_str());
  }
}

void printSummary(const granular::BuildModelsSummary& summary,
                  const granular::ModelBuildConfig& config, double seconds) {
  for (const std::string& line : summary.cleared) {
    std::fprintf(stderr, "cleared: %s\n", line.c_str());
  }
  for (const std::string& warning : summary.warnings) {
    std::fprintf(stderr, "warning: %s\n", warning.c_str());
  }
  const granular::FilterStage all[] = {
      granular::FilterStage::kPassThrough, granular::FilterStage::kRadiusOutlier,
      granular::FilterStage::kStatisticalOutlier, granular::FilterStage::kVoxelGrid};
  std::printf("models (%s concatenation; points after each filter stage, '-' not run):\n",
              granular::methodName(config.method));
  // The class column as wide as the longest label, so that long real labels keep the table.
  int width = 12;
  for (const granular::ClassModelSummary& model : summary.classes) {
    width = std::max(width, static_cast<int>(model.label.size()));
  }
  std::printf("  %-*s %8s %8s %9s", width, "class", "objects", "kept", "raw");
  for (const granular::FilterStage stage : all) {
    std::printf(" %19s", granular::stageName(stage));
  }
  std::printf(" %8s\n", "seconds");
  for (const granular::ClassModelSummary& model : summary.classes) {
    std::printf("  %-*s %8zu %8zu %9zu", width, model.label.c_str(), model.objects, model.kept,
                model.raw_points);
    for (const granular::FilterStage stage : all) {
      std::string cell = "-";
      for (const granular::StageResult& result : model.stages) {
        if (result.stage == stage) {
          cell = std::to_string(result.points);
        }
      }
      std::printf(" %19s", cell.c_str());
    }
    std::printf(" %8.2f\n", model.seconds);
  }
  std::printf("total: %zu classes, %.2f s\n", summary.classes.size(), seconds);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::ModelBuildConfig config;
  granular::BuildModelsOptions run;
  granular_ros::Tool tool("build_models", usage);
  declareOptions(tool.options(), options);
  const auto configure = [&] {
    config = buildConfig(options);
    if (options.classes) {
      run.classes = granular_ros::splitList("--classes", *options.classes);
    }
  };
  return tool.run(argc, argv, configure, [&] {
    run.output = granular_ros::Tool::outputPolicy(options.overwrite);
    run.mesh = options.mesh;
    run.seeds = options.seeds;
    run.progress = [progress = granular_ros::ProgressReport(4)](
                       const std::string& label, std::size_t done, std::size_t total) mutable {
      progress(label + " aligning", done, total, "objects");
    };
    run.class_done = reportClass;
    const auto start = std::chrono::steady_clock::now();
    const granular::BuildModelsSummary summary =
        granular::buildModels(options.objects, options.out, config, run);
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    printSummary(summary, config, elapsed.count());
  });
}
