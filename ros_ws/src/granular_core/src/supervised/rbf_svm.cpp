#include "granular_core/supervised/rbf_svm.h"

#include <algorithm>
#include <cfloat>

namespace granular {
namespace {

constexpr int kLanes = LaneBlocks::kLanes;
constexpr int kRows = 4;  // samples whose decision sums run side by side

}  // namespace

std::optional<RbfSvmPredictor> RbfSvmPredictor::from(const cv::ml::SVM& svm, int classes) {
  const int type = svm.getType();
  if (!svm.isTrained() || svm.getKernelType() != cv::ml::SVM::RBF || classes < 2 ||
      (type != cv::ml::SVM::C_SVC && type != cv::ml::SVM::NU_SVC)) {
    return std::nullopt;
  }
  RbfSvmPredictor predictor;
  predictor.classes_ = classes;
  predictor.minus_gamma_ = -svm.getGamma();
  const cv::Mat vectors = svm.getSupportVectors();
  if (vectors.type() != CV_32F || vectors.cols != svm.getVarCount() || vectors.rows < 1) {
    return std::nullopt;
  }
  predictor.supports_ = LaneBlocks(vectors);
  try {
    for (int d = 0; d < classes * (classes - 1) / 2; ++d) {
      cv::Mat alpha, support;
      Decision decision;
      decision.rho = svm.getDecisionFunction(d, alpha, support);
      if (alpha.type() != CV_64F || support.type() != CV_32S || alpha.total() != support.total()) {
        return std::nullopt;
      }
      decision.alpha.assign(alpha.ptr<double>(), alpha.ptr<double>() + alpha.total());
      decision.support.assign(support.ptr<int>(), support.ptr<int>() + support.total());
      for (const int s : decision.support) {
        if (s < 0 || s >= vectors.rows) {
          return std::nullopt;
        }
      }
      predictor.decisions_.push_back(std::move(decision));
    }
  } catch (const cv::Exception&) {
    return std::nullopt;  // fewer decision functions: another number of classes
  }
  return predictor;
}

void RbfSvmPredictor::kernel(const float* sample, float* values) const {
  // OpenCV's calc_rbf: per support vector, the float differences squared in double, summed two
  // at a time, times -gamma, to float; then cv::exp over the row and the clamp its calc() ends
  // with. This file is compiled without floating-point contraction, as OpenCV is.
  const int n = supports_.width();
  for (int b = 0; b < supports_.blocks(); ++b) {
    const float* const block = supports_.block(b);
    double sum[kLanes] = {};
    int v = 0;
    for (; v + 4 <= n; v += 4) {
      const float* const row = block + v * kLanes;
      for (int l = 0; l < kLanes; ++l) {
        double t0 = row[l] - sample[v];
        double t1 = row[kLanes + l] - sample[v + 1];
        sum[l] += t0 * t0 + t1 * t1;
        t0 = row[2 * kLanes + l] - sample[v + 2];
        t1 = row[3 * kLanes + l] - sample[v + 3];
        sum[l] += t0 * t0 + t1 * t1;
      }
    }
    for (; v < n; ++v) {
      for (int l = 0; l < kLanes; ++l) {
        const double t0 = block[v * kLanes + l] - sample[v];
        sum[l] += t0 * t0;
      }
    }
    for (int l = 0; l < supports_.lanesIn(b); ++l) {
      values[b * kLanes + l] = static_cast<float>(sum[l] * minus_gamma_);
    }
  }
  cv::Mat row(1, supports_.rows(), CV_32F, values);
  cv::exp(row, row);
  const float most = static_cast<float>(FLT_MAX * 1e-3);
  for (int s = 0; s < supports_.rows(); ++s) {
    values[s] = std::min(values[s], most);
  }
}

void RbfSvmPredictor::vote(const float* const* values, int count, Answer* answers) const {
  std::vector<int> votes(static_cast<std::size_t>(kRows) * classes_, 0);
  std::size_t d = 0;
  for (int i = 0; i < classes_; ++i) {
    for (int j = i + 1; j < classes_; ++j) {
      const Decision& decision = decisions_[d++];
      double sum[kRows];
      std::fill(sum, sum + kRows, -decision.rho);
      for (std::size_t k = 0; k < decision.alpha.size(); ++k) {
        const double alpha = decision.alpha[k];
        const int support = decision.support[k];
        for (int r = 0; r < count; ++r) {
          sum[r] += alpha * values[r][support];
        }
      }
      for (int r = 0; r < count; ++r) {
        ++votes[static_cast<std::size_t>(r) * classes_ + (sum[r] > 0 ? i : j)];
      }
    }
  }
  for (int r = 0; r < count; ++r) {
    const int* const mine = &votes[static_cast<std::size_t>(r) * classes_];
    const int* const most = std::max_element(mine, mine + classes_);  // the first of ties
    answers[r] = {static_cast<int>(most - mine), *most};
  }
}

std::vector<RbfSvmPredictor::Answer> RbfSvmPredictor::predict(const cv::Mat& samples) const {
  CV_Assert(samples.type() == CV_32F && samples.cols == supports_.width());
  std::vector<Answer> answers(static_cast<std::size_t>(samples.rows));
  const int groups = (samples.rows + kRows - 1) / kRows;
  cv::parallel_for_(cv::Range(0, groups), [&](const cv::Range& range) {
    const auto stride = static_cast<std::size_t>(supports_.rows());
    std::vector<float> values(kRows * stride);
    const float* rows[kRows];
    for (int g = range.start; g < range.end; ++g) {
      const int first = g * kRows;
      const int count = std::min(kRows, samples.rows - first);
      for (int r = 0; r < count; ++r) {
        rows[r] = &values[static_cast<std::size_t>(r) * stride];
        kernel(samples.ptr<float>(first + r), &values[static_cast<std::size_t>(r) * stride]);
      }
      vote(rows, count, &answers[static_cast<std::size_t>(first)]);
    }
  });
  return answers;
}

}  // namespace granular
