// Matching map landmarks to the features of a frame: by projection (a predicted position
// and a descriptor) for tracking, and by descriptor alone for relocalisation.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "core/map.h"

namespace plslam {

struct ProjectedPoint {
  Id id;
  Eigen::Vector2d uv;  ///< predicted ideal pixel
  cv::Mat descriptor;  ///< 1x32 CV_8U
};

struct ProjectedLine {
  Id id;
  Eigen::Vector2d p, q;  ///< predicted segment, ideal pixels
  cv::Mat descriptor;
};

struct ProjectionSearchOptions {
  double radius_px = 10;  ///< search window around the prediction
  int max_distance = 75;  ///< Hamming distance accepted
  float ratio = 0.85f;    ///< best must be below ratio * second best (when they are different keypoints)
};

struct LineSearchOptions {
  double angle_deg = 8;      ///< max direction difference
  double distance_px = 8;    ///< max distance of the segment endpoints to the predicted infinite line
  int max_distance = 80;     ///< LBD Hamming distance accepted
};

/// Hamming distance of two 32-byte descriptors.
int hamming32(const uint8_t* a, const uint8_t* b);

/// For each projected point, the index of the matched keypoint or -1. A keypoint goes to
/// the closest descriptor; keypoints already taken in `taken` (!= kNoId) are kept unless a
/// landmark in `projected` is that same one.
std::vector<int> searchPointsByProjection(const std::vector<ProjectedPoint>& projected, const FrameFeatures& f,
                                          const ProjectionSearchOptions& options, const std::vector<Id>& taken);
/// For each projected line, the index of the matched segment or -1.
std::vector<int> searchLinesByProjection(const std::vector<ProjectedLine>& projected, const FrameFeatures& f,
                                         const LineSearchOptions& options, const std::vector<Id>& taken);
/// For each row of `a`, the matching row of `b` or -1 (ratio test, each row of b used once).
std::vector<int> matchDescriptors(const cv::Mat& a, const cv::Mat& b, int max_distance, float ratio);

}  // namespace plslam
