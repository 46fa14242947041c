// evaluate_segmentation: the command-line face of granular::evaluateSegmentation (its options:
// evaluate_segmentation_options.h).
#include <iostream>
#include <memory>
#include <optional>

#include <granular_core/runs/segmentation_run.h>

#include "evaluate_segmentation_options.h"

int main(int argc, char** argv) {
  granular_ros::EvaluateSegmentationOptions options;
  granular::SegmentationStageConfig config;
  granular::GroundConfig ground;
  std::optional<granular::CuboidConfig> cuboids;
  std::optional<granular::SupervisedClassifier> classifier;
  std::unique_ptr<granular::CuboidFitter> fitter;
  granular_ros::Tool tool("evaluate_segmentation");
  options.declareIn(tool);
  const auto configure = [&] {
    options.box_free.frames = options.frames;  // whose clouds --sensor auto measures
    config = options.segmentation();
    ground = options.box_free.ground();
    cuboids = options.cuboids();
    options.checkFigures();
  };
  return tool.run(argc, argv, configure, [&] {
    granular::SegmentationEvaluationOptions& evaluation = options.evaluation;
    if (options.classifier_file) {
      classifier.emplace(granular_ros::loadBackgroundClassifier(*options.classifier_file,
                                                                config.background.label));
      evaluation.classifier = &*classifier;
    }
    if (cuboids) {
      fitter = granular::makeCuboidFitter(*cuboids, {});
      evaluation.cuboids = fitter.get();
      evaluation.free_space = cuboids->free_space;
    }
    evaluation.save = options.save;
    evaluation.save_policy = granular_ros::Tool::outputPolicy(options.overwrite);
    evaluation.progress = tool.progress("segmenting", "clouds");
    granular::evaluateSegmentation(options.frames, ground, config, evaluation).report(std::cout);
  });
}
