// The Background decision on one segment, made the same way by evaluate_segmentation and
// fit_cuboids.
#pragma once

#include <string>

#include "granular_core/extraction/extract_objects.h"
#include "granular_core/segmentation/background.h"
#include "granular_core/supervised/supervised_classifier.h"

namespace granular {
namespace runs {

struct BackgroundDecision {
  std::string label;     ///< the classifier's answer
  double score = 0.0;    ///< and its score (SupervisedPrediction::score)
  bool dropped = false;  ///< calledBackground: the segment is background
};

/// The classifier's answer on the frame's points in the segment's `box` (in its object frame),
/// and whether it drops the segment.
inline BackgroundDecision decideBackground(const SupervisedClassifier& classifier,
                                           const FrameCropper& frame, const OrientedBox& box,
                                           const BackgroundConfig& config) {
  const Cloud object = frame.crop(box, Eigen::Vector3d::Zero());
  const SupervisedPrediction answer = classifier.predictWithScore(classifier.features(object));
  return {answer.label, answer.score,
          calledBackground(answer.label, answer.score, object.size(),
                           box.centre().head<2>().norm(), config)};
}

}  // namespace runs
}  // namespace granular
