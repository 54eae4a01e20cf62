// Pixel overlap of predicted object masks with the true ones, summed over frames:
// precision (predicted pixels that are object pixels), recall (object pixels that are
// predicted) and intersection over union.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace plslam {

struct MaskOverlap {
  int64_t true_positive = 0;   ///< predicted and true
  int64_t false_positive = 0;  ///< predicted, not true
  int64_t false_negative = 0;  ///< true, not predicted

  /// Adds one frame: the non-zero pixels of `predicted` and of `truth` (single channel, same
  /// size) are object pixels. An empty `predicted` predicts none. Throws DataError otherwise.
  void add(const cv::Mat& predicted, const cv::Mat& truth);
  double precision() const;  ///< 1 when nothing was predicted
  double recall() const;     ///< 1 when there was nothing to find
  double iou() const;        ///< 1 when both are empty
};

}  // namespace plslam
