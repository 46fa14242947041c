// build_models: the command-line face of granular::buildModels, one model per class.
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include <granular_core/runs/build_models_run.h>

#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

int main(int argc, char** argv) {
  std::string objects, out;
  std::optional<std::string> config_file, method, classes;
  granular::BuildModelsOptions run;
  bool overwrite = false;
  granular_ros::Tool tool(
      "build_models",
      "usage: build_models --objects FOLDER --out FOLDER [options]\n\n"
      "Stacks the object PCDs of each class of an objects folder (<Class>-<stamp>-<index>\n"
      ".pcd, as extract_objects writes them) into one model per class and filters it (report\n"
      "sections 5.2 and 5.3). Writes OUT/<Class>.pcd (filtered, fields x y z), OUT/raw/\n"
      "<Class>.pcd (concatenated), OUT/models.json (objects used and kept, points after each\n"
      "stage, parameters) and, with --mesh, OUT/mesh/<Class>.ply. A class with fewer\n"
      "than min_objects objects, or whose filtered model has fewer than min_points points\n"
      "(--config), is left out with a warning naming it and why (also in models.json's\n"
      "left_out); the run fails only when no class is left. Needs no roscore.\n",
      "Progress goes to stderr, the summary table to stdout. --out is built beside itself\n"
      "and put in place when complete; a second run into it is refused meanwhile. Exit\n"
      "status: 0 done, 1 failed (unreadable input, no objects, no class left with a\n"
      "model, output not writable or holding results without --overwrite), 2 bad option or\n"
      "configuration, 130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP (nothing left half\n"
      "written).\n\n"
      "configuration keys (--config) and their defaults; class_filters holds per-class\n"
      "changes to filters in the same layout:\n" +
          granular_ros::configurationHelp<granular::ModelBuildConfig>());
  tool.options()
      .required("--objects", objects, "FOLDER", "objects folder to read")
      .required("--out", out, "FOLDER", "models folder to create")
      .value("--method", method, "plain|icp",
             "plain concatenation, or each object aligned to the growing model with ICP and "
             "kept if it converged with a good fit (default " +
                 std::string(granular::methodName(granular::ModelBuildConfig().method)) + ")")
      .keyValues("--seed", run.seeds, "CLASS=FILE.pcd",
                 "ICP seed model of CLASS (a PCD in the object frame); repeat for several "
                 "classes. Default: the objects with most points showing each side (front, "
                 "back, left, right)")
      .value("--classes", classes, "LIST",
             "classes to build, comma-separated, e.g. Sedan,SUV (default: every class in the "
             "folder)")
      .value("--config", config_file, "FILE",
             "YAML file with method, seed, icp, filters, class_filters and mesh (the "
             "repository's config/models.yaml documents them); options above override it")
      .flag("--mesh", run.mesh, "also write a triangle mesh of each model")
      .flag("--overwrite", overwrite,
            "replace --out when a granular tool wrote it (a folder of other files is never "
            "replaced)");
  granular::ModelBuildConfig config;
  const auto configure = [&] {
    using Method = granular::ConcatenationMethod;
    config = granular_ros::buildConfig<granular::ModelBuildConfig>(config_file, [&](auto& loaded) {
      loaded.method = method ? granular_ros::parseChoice<Method>("--method", *method) : loaded.method;
    });
    if (classes) {
      run.classes = granular_ros::splitList("--classes", *classes);
    }
  };
  return tool.run(argc, argv, configure, [&] {
    run.output = granular_ros::Tool::outputPolicy(overwrite);
    run.progress = [progress = granular_ros::ProgressReport(4)](
                       const std::string& label, std::size_t done, std::size_t total) mutable {
      progress(label + " aligning", done, total, "objects");
    };
    run.class_done = [](const granular::ClassModelSummary& model) {
      granular::BuildModelsSummary::reportClass(model, std::cerr);
    };
    granular::buildModels(objects, out, config, run).report(std::cout, std::cerr);
  });
}
