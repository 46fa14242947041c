// build_models: the command-line face of granular::buildModels. Reads options and an optional
// YAML config, builds one model per class, reports progress on stderr and a table on stdout.
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/runs/build_models_run.h>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

std::string usage() {
  const granular::ModelBuildConfig defaults;
  std::ostringstream text;
  text << "usage: build_models --objects FOLDER --out FOLDER [options]\n"
          "\n"
          "Stacks the object PCDs of each class of an objects folder (<Class>-<stamp>-<index>\n"
          ".pcd, as extract_objects writes them) into one model per class and filters it (report\n"
          "sections 5.2 and 5.3). Writes OUT/<Class>.pcd (filtered, fields x y z), OUT/raw/\n"
          "<Class>.pcd (concatenated), OUT/models.json (objects used and kept, points after each\n"
          "stage, parameters) and, with --mesh, OUT/mesh/<Class>.ply. A class with fewer\n"
          "than min_objects objects, or whose filtered model has fewer than min_points points\n"
          "(--config), is left out with a warning naming it and why (also in models.json's\n"
          "left_out); the run fails only when no class is left. Needs no roscore.\n"
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
          "  -h, --help           print this help and exit\n"
          "\n"
          "Progress goes to stderr, the summary table to stdout. --out is built beside itself\n"
          "and put in place when complete; a second run into it is refused meanwhile. Exit\n"
          "status: 0 done, 1 failed (unreadable input, no objects, no class left with a\n"
          "model, output not writable or holding results without --overwrite), 2 bad option or configuration, 130/143/129\n"
          "interrupted by SIGINT/SIGTERM/SIGHUP (nothing left half written).\n"
          "\n"
          "configuration keys (--config) and their defaults; class_filters holds per-class\n"
          "changes to filters in the same layout:\n"
       << granular_ros::configurationHelp(defaults);
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
granular::ModelBuildConfig buildModelConfig(const Options& options) {
  return granular_ros::buildConfig<granular::ModelBuildConfig>(
      options.config_file, [&](granular::ModelBuildConfig& config) {
        if (options.method) {
          const auto method = granular::methodFromName(*options.method);
          if (!method) {
            throw std::invalid_argument("--method: expected plain or icp, got '" +
                                        *options.method + "'");
          }
          config.method = *method;
        }
      });
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::ModelBuildConfig config;
  granular::BuildModelsOptions run;
  granular_ros::Tool tool("build_models", usage);
  declareOptions(tool.options(), options);
  const auto configure = [&] {
    config = buildModelConfig(options);
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
    run.class_done = [](const granular::ClassModelSummary& model) {
      granular::BuildModelsSummary::reportClass(model, std::cerr);
    };
    granular::buildModels(options.objects, options.out, config, run).report(std::cout, std::cerr);
  });
}
