// ORB keypoints spread over the image, with a mask that forbids regions.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace plslam {

struct OrbOptions {
  int num_features = 1000;     ///< keypoints kept per image
  float scale_factor = 1.2f;   ///< pyramid scale between levels
  int num_levels = 8;          ///< pyramid levels
  int fast_threshold = 20;     ///< FAST threshold
  int min_fast_threshold = 7;  ///< retried with this when the image yields too few keypoints
  int grid_cols = 16;          ///< the image is split into grid_cols x grid_rows cells and
  int grid_rows = 12;          ///< each cell keeps its share of the strongest keypoints
};

/// Detects and describes ORB keypoints on a grey image. `mask` (CV_8U, same size; empty =
/// everything allowed) forbids keypoints where it is 0. Descriptors: CV_8U, one 32-byte row
/// per keypoint. Empty or tiny images give no keypoints.
void extractOrb(const cv::Mat& grey, const cv::Mat& mask, const OrbOptions& options, std::vector<cv::KeyPoint>* keypoints,
                cv::Mat* descriptors);

}  // namespace plslam
