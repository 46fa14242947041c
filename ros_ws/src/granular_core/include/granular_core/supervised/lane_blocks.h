#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace granular {

/// The rows of a CV_32F matrix in blocks of kLanes rows, value v of row l of a block at
/// [v * kLanes + l], the last block padded with zeros: the layout in which RbfSvmPredictor and
/// KnnPredictor run OpenCV's arithmetic for one row over kLanes rows side by side.
class LaneBlocks {
 public:
  static constexpr int kLanes = 8;

  LaneBlocks() = default;
  explicit LaneBlocks(const cv::Mat& rows) : rows_(rows.rows), width_(rows.cols) {
    CV_Assert(rows.type() == CV_32F);
    values_.assign(static_cast<std::size_t>(blocks()) * width_ * kLanes, 0.0f);
    for (int r = 0; r < rows_; ++r) {
      float* const first = &values_[static_cast<std::size_t>(r / kLanes) * width_ * kLanes];
      for (int v = 0; v < width_; ++v) {
        first[v * kLanes + r % kLanes] = rows.at<float>(r, v);
      }
    }
  }

  int rows() const { return rows_; }
  int width() const { return width_; }
  int blocks() const { return (rows_ + kLanes - 1) / kLanes; }
  /// Block b's values: value v of its row l at [v * kLanes + l].
  const float* block(int b) const {
    return &values_[static_cast<std::size_t>(b) * width_ * kLanes];
  }
  /// The rows block b holds (kLanes but in the last block).
  int lanesIn(int b) const { return std::min(kLanes, rows_ - b * kLanes); }

 private:
  int rows_ = 0;
  int width_ = 0;
  std::vector<float> values_;
};

}  // namespace granular
