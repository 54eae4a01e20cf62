// Line segments: LSD, then a merge of collinear fragments (LSD over-segments: one physical
// edge comes out as several pieces), a length filter and a cap; LBD descriptors.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace plslam {

struct LineOptions {
  double detect_scale = 0.5;       ///< LSD runs on the image resized by this (speed; edges survive)
  double min_length_ratio = 0.04;  ///< segments shorter than this fraction of the image diagonal are dropped
  int max_lines = 120;             ///< keep at most this many (the longest)
  double merge_angle_deg = 3.0;    ///< fragments closer than this in direction...
  double merge_distance_px = 2.0;  ///< ...whose endpoints lie this close to each other's line...
  double merge_gap_px = 12.0;      ///< ...and that are at most this far apart along it are merged
  double masked_fraction = 0.3;    ///< a segment with more than this fraction of its samples masked is dropped
  double lbd_scale = 0.5;          ///< LBD is computed on the image resized by this (speed)
};

struct LineSegment2D {
  Eigen::Vector2d p, q;  ///< endpoints, pixels of the input image
  double length() const { return (q - p).norm(); }
};

/// What the stages kept, for statistics.
struct LineStats {
  int detected = 0;  ///< raw LSD segments
  int merged = 0;    ///< after merging fragments
  int kept = 0;      ///< after the length filter, mask and cap
};

/// LSD + merge + filter on a grey image (CV_8U). `mask` (CV_8U, 0 = forbidden; may be empty).
std::vector<LineSegment2D> detectLines(const cv::Mat& grey, const cv::Mat& mask, const LineOptions& options,
                                       LineStats* stats = nullptr);
/// Joins collinear fragments (exposed for tests). Deterministic.
std::vector<LineSegment2D> mergeSegments(std::vector<LineSegment2D> segments, const LineOptions& options);
/// LBD descriptors (CV_8U, 32 bytes a row, one row per segment, same order).
cv::Mat describeLines(const cv::Mat& grey, const std::vector<LineSegment2D>& lines, const LineOptions& options);

}  // namespace plslam
