// The Line Segment Detector of Grompone von Gioi, Jakubowicz, Morel and Randall ("LSD: a
// Line Segment Detector", IPOL 2012) in the form plslam runs it: Gaussian sub-sampling,
// the level-line field of 2 x 2 gradients, seeds taken in decreasing gradient order
// (pseudo-ordered in bins), regions grown over aligned neighbours and each region's
// rectangle by its inertia axis; no a-contrario validation and no refinement, as OpenCV's
// LSD_REFINE_NONE mode. Written for speed: OpenCV's implementation sorts every pixel of the
// image with a comparison sort (about half its time on a 320 x 240 image, see
// docs/RESULTS.md "Our own LSD"); here only the pixels above the gradient threshold are
// ordered, by counting into the bins.
//
// Stateless and deterministic. Thread safety: may be called concurrently.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace plslam {

struct LsdParameters {
  double scale = 0.8;         ///< the image is sub-sampled by this first, (0, 1]
  double sigma_scale = 0.6;   ///< Gaussian sigma of the sub-sampling = sigma_scale / scale
  double quant = 2.0;         ///< bound on the gradient's quantisation error (sets its threshold)
  double angle_tol_deg = 22.5;  ///< a pixel joins a region within this of the region's angle
  int bins = 1024;            ///< bins of the pseudo-ordering by gradient norm
};

/// Segments of a CV_8UC1 image as (x1, y1, x2, y2), in the coordinates OpenCV's
/// `LineSegmentDetector::detect` gives for the same image and scale: walking from the first
/// point to the second, the darker side is on the right. Throws DataError for another image
/// type, ConfigError for parameters out of range.
std::vector<cv::Vec4f> detectLsdSegments(const cv::Mat& grey, const LsdParameters& parameters);

}  // namespace plslam
