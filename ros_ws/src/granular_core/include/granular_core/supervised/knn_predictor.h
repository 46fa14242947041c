#pragma once

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

#include "granular_core/supervised/lane_blocks.h"

namespace granular {

/// The answers of cv::ml::KNearest::findNearest (brute force, a classifier), bit for bit: the
/// same float distances summed in the same order, the same nearest k (ties keep the earlier
/// training sample first) and the same majority (ties: the smaller response). OpenCV computes
/// one distance after the other; here eight training samples at a time, which the processor
/// runs side by side.
class KnnPredictor {
 public:
  /// `samples`: the training rows (CV_32F), `responses`: one value each (CV_32F, as
  /// KNearest keeps them), `k`: the neighbours that vote. Throws std::invalid_argument for
  /// empty or mismatched inputs or k < 1.
  KnnPredictor(const cv::Mat& samples, const cv::Mat& responses, int k);

  /// One query's answer: the response, and how many of its neighbours() have it.
  struct Answer {
    float response = 0.0f;
    int votes = 0;
  };

  /// The answer for each row of `queries` (CV_32F, the training rows' width), spread over
  /// OpenCV's threads as findNearest does.
  std::vector<Answer> predict(const cv::Mat& queries) const;

  /// The neighbours that vote: k, or every training sample when there are fewer.
  int neighbours() const { return std::min(k_, samples_.rows()); }

 private:
  Answer answer(const float* query, std::vector<float>& distances,
                std::vector<float>& nearest) const;

  int k_ = 1;
  LaneBlocks samples_;  // the training rows
  std::vector<float> responses_;
};

}  // namespace granular
