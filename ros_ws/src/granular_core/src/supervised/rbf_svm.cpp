#include "granular_core/supervised/rbf_svm.h"

#include <algorithm>
#include <cfloat>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace granular {
namespace {

constexpr int kLanes = LaneBlocks::kLanes;
constexpr int kRows = 4;  // samples whose decision sums run side by side

// OpenCV's calc_rbf sums for the kLanes support vectors of one block (value v of lane l at
// block[v * kLanes + l]) against `sample` of n values: per support vector, the float
// differences squared in double, summed two at a time. This file is compiled without
// floating-point contraction, as OpenCV is.
void blockSums(const float* block, const float* sample, int n, double* sum) {
  std::fill(sum, sum + kLanes, 0.0);
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
}

#if defined(__x86_64__)
static_assert(kLanes == 8, "one block of support vectors is one AVX register of floats");

// The squares, in double, of the eight float differences `row - value`: lanes 0-3 and 4-7.
__attribute__((target("avx2"))) inline void squaredDifferences(const float* row, float value,
                                                               __m256d& low, __m256d& high) {
  const __m256 difference = _mm256_sub_ps(_mm256_loadu_ps(row), _mm256_set1_ps(value));
  low = _mm256_cvtps_pd(_mm256_castps256_ps128(difference));
  high = _mm256_cvtps_pd(_mm256_extractf128_ps(difference, 1));
  low = _mm256_mul_pd(low, low);
  high = _mm256_mul_pd(high, high);
}

// blockSums with AVX2, the same IEEE operations in the same order: the compiler vectorises the
// scalar loop poorly (more instructions with AVX2 than without), here a block is two registers.
__attribute__((target("avx2"))) void blockSumsAvx2(const float* block, const float* sample,
                                                   int n, double* sum) {
  __m256d low = _mm256_setzero_pd(), high = _mm256_setzero_pd();
  __m256d low0, high0, low1, high1;
  int v = 0;
  for (; v + 4 <= n; v += 4) {  // pairs only within fours, as blockSums
    for (int pair = v; pair < v + 4; pair += 2) {
      squaredDifferences(block + pair * kLanes, sample[pair], low0, high0);
      squaredDifferences(block + (pair + 1) * kLanes, sample[pair + 1], low1, high1);
      low = _mm256_add_pd(low, _mm256_add_pd(low0, low1));
      high = _mm256_add_pd(high, _mm256_add_pd(high0, high1));
    }
  }
  for (; v < n; ++v) {
    squaredDifferences(block + v * kLanes, sample[v], low0, high0);
    low = _mm256_add_pd(low, low0);
    high = _mm256_add_pd(high, high0);
  }
  _mm256_storeu_pd(sum, low);
  _mm256_storeu_pd(sum + 4, high);
}
#endif

}  // namespace

bool RbfSvmPredictor::avx2Available() {
#if defined(__x86_64__)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

std::optional<RbfSvmPredictor> RbfSvmPredictor::from(const cv::ml::SVM& svm, int classes,
                                                     Instructions instructions) {
  const int type = svm.getType();
  if (!svm.isTrained() || svm.getKernelType() != cv::ml::SVM::RBF || classes < 2 ||
      (type != cv::ml::SVM::C_SVC && type != cv::ml::SVM::NU_SVC)) {
    return std::nullopt;
  }
  RbfSvmPredictor predictor;
  predictor.avx2_ = instructions == Instructions::kBest && avx2Available();
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
  // OpenCV's calc_rbf: the sums, times -gamma, to float; then cv::exp over the row and the
  // clamp its calc() ends with.
  const int n = supports_.width();
  double sum[kLanes];
  for (int b = 0; b < supports_.blocks(); ++b) {
#if defined(__x86_64__)
    if (avx2_) {
      blockSumsAvx2(supports_.block(b), sample, n, sum);
    } else {
      blockSums(supports_.block(b), sample, n, sum);
    }
#else
    blockSums(supports_.block(b), sample, n, sum);
#endif
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

std::vector<float> RbfSvmPredictor::kernelRow(const float* sample) const {
  std::vector<float> values(static_cast<std::size_t>(supports_.rows()));
  kernel(sample, values.data());
  return values;
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
