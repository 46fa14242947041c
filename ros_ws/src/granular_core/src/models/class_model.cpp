#include "granular_core/models/class_model.h"

#include <algorithm>
#include <chrono>

#include "granular_core/models/concatenate.h"
#include "granular_core/models/icp_concatenate.h"
#include "granular_core/text.h"

namespace granular {

ClassModel buildClassModel(const std::string& label, const std::vector<ModelCloud>& objects,
                           const ModelBuildConfig& config, const ModelCloud* seed,
                           const std::function<void(std::size_t, std::size_t)>& progress,
                           const std::vector<double>& box_heights) {
  const auto start = std::chrono::steady_clock::now();
  ClassModel result;
  ClassModelSummary& summary = result.summary;
  summary.label = label;
  summary.objects = objects.size();
  summary.filters = config.filtersFor(label);
  if (objects.empty()) {
    summary.warnings.push_back("no objects of this class");
    return result;
  }

  if (config.method == ConcatenationMethod::kPlain) {
    result.raw = concatenate(objects);
    summary.kept = objects.size();
  } else {
    ModelCloud start_model;
    if (seed != nullptr) {
      summary.seed_source = "file";
      start_model = *seed;
    } else {
      summary.seed_source = "auto";
      const SeedSelection selection = selectSeedObjects(objects, config.seed);
      std::vector<ModelCloud> chosen;
      for (const std::size_t index : selection.indices) {
        chosen.push_back(objects[index]);
      }
      start_model = concatenate(chosen);
      summary.seed_objects = selection.indices;
      for (const Side side : selection.missing_sides) {
        summary.missing_sides.push_back(sideName(side));
      }
      if (objects.size() == 1) {
        summary.warnings.push_back("a single object: ICP has nothing to align, the model is "
                                   "that object");
      } else if (!summary.missing_sides.empty()) {
        summary.warnings.push_back("the automatic ICP seed shows no " +
                                   joined(summary.missing_sides) + " side");
      }
    }
    summary.seed_points = start_model.size();
    IcpConcatenation icp =
        concatenateWithIcp(objects, start_model, summary.seed_objects, config.icp, progress);
    result.raw = std::move(icp.model);
    summary.kept = icp.kept;
    std::vector<bool> in_seed(objects.size(), false);
    for (const std::size_t index : summary.seed_objects) {
      in_seed[index] = true;
    }
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (in_seed[i]) {
        continue;
      }
      const Alignment& alignment = icp.alignments[i];
      ++summary.verdicts[verdictName(alignment.verdict)];
      if (alignment.verdict != IcpVerdict::kTooFewPoints) {
        ++summary.convergence[convergenceName(alignment.convergence)];
      }
    }
  }

  summary.raw_points = result.raw.size();
  if (!summary.filters.pass_through.max_z) {
    std::vector<double> heights = box_heights;
    if (heights.empty()) {
      for (const ModelCloud& object : objects) {
        double top = 0.0;
        for (const pcl::PointXYZ& point : object.points) {
          top = std::max(top, static_cast<double>(point.z));
        }
        heights.push_back(top);
      }
    }
    summary.filters.pass_through.max_z = autoMaxZ(heights);
  }
  result.model = applyFilterChain(result.raw, summary.filters, &summary.stages);
  summary.points = result.model.size();
  if (result.model.empty()) {
    for (const StageResult& stage : summary.stages) {
      if (stage.points == 0 && !summary.emptied_by) {
        summary.emptied_by = stage.stage;
      }
    }
    summary.warnings.push_back(
        summary.emptied_by
            ? std::string("the ") + stageName(*summary.emptied_by) + " stage left no points"
            : std::string("the filter chain left no points"));
  }
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace granular
