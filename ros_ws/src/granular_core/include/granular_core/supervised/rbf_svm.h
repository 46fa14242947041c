#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "granular_core/supervised/lane_blocks.h"

namespace granular {

/// The class answers of a trained one-vs-one cv::ml::SVM with an RBF kernel (C or nu
/// classification), the same as its predict() gives, bit for bit: the same arithmetic in the
/// same order. OpenCV's loop adds one double to the next for each support vector in turn, so
/// it waits on every addition (77 us per object for 1,500 support vectors of 60 values); here
/// the kernel runs over several support vectors at once and the decision sums of several
/// samples are interleaved, which the processor overlaps.
class RbfSvmPredictor {
 public:
  /// Which instructions the kernel runs on; both give the same answers, bit for bit.
  enum class Instructions {
    kBest,      ///< AVX2 where the processor has it (avx2Available()), else the baseline
    kBaseline,  ///< what the build targets (x86-64: SSE2)
  };
  static bool avx2Available();

  /// None when `svm` is not an RBF C or nu classifier with `classes` classes numbered
  /// 0 .. classes - 1 (how SupervisedClassifier trains it): then use svm.predict().
  static std::optional<RbfSvmPredictor> from(const cv::ml::SVM& svm, int classes,
                                             Instructions instructions = Instructions::kBest);

  /// One sample's answer: the class predict() gives, and how many of its one-vs-one duels
  /// that class won (classes - 1 at most).
  struct Answer {
    int label = 0;
    int votes = 0;
  };

  /// The answer for each row of `samples` (CV_32F, one sample a row, as many columns as the
  /// SVM's variables), spread over OpenCV's threads as predict() does.
  std::vector<Answer> predict(const cv::Mat& samples) const;

  /// The kernel values of one sample (the SVM's variables, as floats) against the support
  /// vectors, one per support vector, as OpenCV's calc_rbf leaves them: what the decisions are
  /// summed from.
  std::vector<float> kernelRow(const float* sample) const;

 private:
  RbfSvmPredictor() = default;

  // The kernel of one sample against every support vector, as OpenCV's calc_rbf leaves it.
  void kernel(const float* sample, float* values) const;
  // The answer for each of `count` samples (at most kRows) from their kernel values.
  void vote(const float* const* values, int count, Answer* answers) const;

  struct Decision {
    double rho = 0.0;
    std::vector<double> alpha;
    std::vector<int> support;  // indices into the support vectors
  };

  bool avx2_ = false;
  int classes_ = 0;
  double minus_gamma_ = 0.0;
  LaneBlocks supports_;  // the support vectors
  std::vector<Decision> decisions_;  // (0,1), (0,2) ... (1,2) ..., as OpenCV orders them
};

}  // namespace granular
