#include "features/orb_extractor.h"

#include <algorithm>
#include <opencv2/features2d.hpp>

namespace plslam {

namespace {

// Keeps about `n` keypoints, spread: each grid cell first contributes its strongest ones
// up to an equal share, then the remaining budget goes to the strongest left anywhere.
std::vector<cv::KeyPoint> distribute(std::vector<cv::KeyPoint> kps, int n, cv::Size size, int cols, int rows) {
  if (static_cast<int>(kps.size()) <= n) return kps;
  std::stable_sort(kps.begin(), kps.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  const int share = std::max(1, n / (cols * rows));
  std::vector<int> used(static_cast<size_t>(cols) * rows, 0);
  std::vector<cv::KeyPoint> kept, rest;
  kept.reserve(n);
  for (const cv::KeyPoint& k : kps) {
    const int cx = std::min(cols - 1, std::max(0, static_cast<int>(k.pt.x * cols / size.width)));
    const int cy = std::min(rows - 1, std::max(0, static_cast<int>(k.pt.y * rows / size.height)));
    int& u = used[static_cast<size_t>(cy) * cols + cx];
    if (u < share) {
      ++u;
      kept.push_back(k);
    } else {
      rest.push_back(k);
    }
  }
  for (size_t i = 0; i < rest.size() && static_cast<int>(kept.size()) < n; ++i) kept.push_back(rest[i]);
  if (static_cast<int>(kept.size()) > n) kept.resize(n);
  return kept;
}

}  // namespace

void extractOrb(const cv::Mat& grey, const cv::Mat& mask, const OrbOptions& o, std::vector<cv::KeyPoint>* keypoints,
                cv::Mat* descriptors) {
  keypoints->clear();
  *descriptors = cv::Mat(0, 32, CV_8U);
  // ORB needs room for its 31-pixel patch at every level.
  if (grey.empty() || grey.cols < 64 || grey.rows < 64 || o.num_features <= 0) return;
  CV_Assert(grey.type() == CV_8UC1);
  cv::Mat m = mask;
  if (!m.empty() && (m.size() != grey.size() || m.type() != CV_8UC1)) m = cv::Mat();
  std::vector<cv::KeyPoint> kps;
  for (int threshold : {o.fast_threshold, o.min_fast_threshold}) {
    // Detect more than needed, then spread them over the grid.
    auto orb = cv::ORB::create(o.num_features * 2, o.scale_factor, o.num_levels, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31,
                               threshold);
    kps.clear();
    orb->detect(grey, kps, m);
    if (static_cast<int>(kps.size()) >= o.num_features / 2 || threshold == o.min_fast_threshold) break;
  }
  kps = distribute(std::move(kps), o.num_features, grey.size(), o.grid_cols, o.grid_rows);
  if (kps.empty()) return;
  auto orb = cv::ORB::create(o.num_features * 2, o.scale_factor, o.num_levels, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31,
                             o.fast_threshold);
  orb->compute(grey, kps, *descriptors);
  *keypoints = std::move(kps);
  if (descriptors->empty()) *descriptors = cv::Mat(0, 32, CV_8U);
}

}  // namespace plslam
