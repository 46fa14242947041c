#include "granular_core/supervised/knn_predictor.h"

#include <algorithm>
#include <cfloat>
#include <stdexcept>

namespace granular {
namespace {

constexpr int kLanes = LaneBlocks::kLanes;

}  // namespace

KnnPredictor::KnnPredictor(const cv::Mat& samples, const cv::Mat& responses, int k)
    : k_(k) {
  if (samples.type() != CV_32F || samples.empty() || responses.type() != CV_32F ||
      static_cast<int>(responses.total()) != samples.rows || k < 1) {
    throw std::invalid_argument("KnnPredictor: needs float training rows, one float response "
                                "each, and k >= 1");
  }
  samples_ = LaneBlocks(samples);
  const cv::Mat column = responses.reshape(1, samples.rows);
  responses_.assign(column.begin<float>(), column.end<float>());
}

KnnPredictor::Answer KnnPredictor::answer(const float* query, std::vector<float>& distances,
                                          std::vector<float>& nearest) const {
  // OpenCV's findNearestCore: per training sample, the float differences squared and summed
  // four at a time, then one at a time; this file is compiled without contraction, as OpenCV
  // is. The nearest k kept sorted by distance, a new one after those as near as it.
  const int k = neighbours();
  distances.assign(static_cast<std::size_t>(k), FLT_MAX);
  nearest.assign(static_cast<std::size_t>(k), 0.0f);
  const int n = samples_.width();
  for (int b = 0; b < samples_.blocks(); ++b) {
    const float* const block = samples_.block(b);
    float sum[kLanes] = {};
    int v = 0;
    for (; v + 4 <= n; v += 4) {
      const float* const row = block + v * kLanes;
      for (int l = 0; l < kLanes; ++l) {
        const float t0 = query[v] - row[l];
        const float t1 = query[v + 1] - row[kLanes + l];
        const float t2 = query[v + 2] - row[2 * kLanes + l];
        const float t3 = query[v + 3] - row[3 * kLanes + l];
        sum[l] += t0 * t0 + t1 * t1 + t2 * t2 + t3 * t3;
      }
    }
    for (; v < n; ++v) {
      for (int l = 0; l < kLanes; ++l) {
        const float t0 = query[v] - block[v * kLanes + l];
        sum[l] += t0 * t0;
      }
    }
    // Most blocks hold none nearer than the k-th so far: one test for all eight lanes (the
    // padding lanes of the last block are skipped below).
    const float farthest = distances[static_cast<std::size_t>(k - 1)];
    bool nearer = false;
    for (int l = 0; l < kLanes; ++l) {
      nearer |= sum[l] < farthest;
    }
    if (!nearer) {
      continue;
    }
    for (int l = 0; l < samples_.lanesIn(b); ++l) {
      const float distance = sum[l];
      if (distance >= distances[static_cast<std::size_t>(k - 1)]) {
        continue;
      }
      int at = k - 1;
      while (at > 0 && distance < distances[static_cast<std::size_t>(at - 1)]) {
        distances[static_cast<std::size_t>(at)] = distances[static_cast<std::size_t>(at - 1)];
        nearest[static_cast<std::size_t>(at)] = nearest[static_cast<std::size_t>(at - 1)];
        --at;
      }
      distances[static_cast<std::size_t>(at)] = distance;
      nearest[static_cast<std::size_t>(at)] = responses_[static_cast<std::size_t>(b * kLanes + l)];
    }
  }
  // The majority: the responses sorted, the first longest run (`distances` is free now).
  std::vector<float>& sorted = distances;
  sorted = nearest;
  std::sort(sorted.begin(), sorted.end());
  Answer result{sorted.front(), 0};
  int best = 0, run_start = 0;
  for (int j = 1; j <= k; ++j) {
    if (j == k || sorted[static_cast<std::size_t>(j)] != sorted[static_cast<std::size_t>(j - 1)]) {
      if (best < j - run_start) {
        best = j - run_start;
        result.response = sorted[static_cast<std::size_t>(j - 1)];
      }
      run_start = j;
    }
  }
  result.votes = static_cast<int>(std::count(nearest.begin(), nearest.end(), result.response));
  return result;
}

std::vector<KnnPredictor::Answer> KnnPredictor::predict(const cv::Mat& queries) const {
  CV_Assert(queries.type() == CV_32F && queries.cols == samples_.width());
  std::vector<Answer> answers(static_cast<std::size_t>(queries.rows));
  cv::parallel_for_(cv::Range(0, queries.rows), [&](const cv::Range& range) {
    std::vector<float> distances, nearest;
    for (int r = range.start; r < range.end; ++r) {
      answers[static_cast<std::size_t>(r)] = answer(queries.ptr<float>(r), distances, nearest);
    }
  });
  return answers;
}

}  // namespace granular
