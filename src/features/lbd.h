// The LBD line descriptor (Zhang and Koch, "An efficient and robust line segment matching
// approach based on LBD descriptor and pairwise geometric consistency", JVCIR 2013) in
// OpenCV's binary form: 9 bands of 7 rows along the segment, 8 gradient statistics per band,
// 32 bytes from comparing the bands pairwise.
//
// The bits are those of cv::line_descriptor::BinaryDescriptor::compute with one octave
// (tests/features/test_lbd.cpp compares the two on random images and segments), so maps
// and the line vocabulary made with either stay valid. It is written for speed: OpenCV's
// version rounds each of the 63 x length samples with a libm call and branches on the sign
// of each gradient; here four rows of the support region advance together, branch-free
// (the LBD stage on fr3: 1.6 ms against 6.3-6.4 ms; docs/RESULTS.md, "LBD without
// OpenCV's loop").
// Built with -ffp-contract=off: a fused multiply-add would change the bits.
//
// Stateless. Thread safety: may be called concurrently.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace plslam {

/// A segment to describe, in pixels of the image handed to describeLbd.
struct LbdSegment {
  float start_x = 0, start_y = 0, end_x = 0, end_y = 0;
  float angle = 0;     ///< direction start -> end, radians (atan2)
  int samples = 1;     ///< samples along the segment, one per pixel of its length
};

/// 32-byte LBD descriptors (CV_8U, one row per segment) of `segments` on the 8-bit grey
/// `image`. An empty list gives a 0 x 32 matrix. Throws Error for an image that is not 8-bit
/// grey, for segments on an empty image and for a segment of fewer than one sample.
cv::Mat describeLbd(const cv::Mat& image, const std::vector<LbdSegment>& segments);

}  // namespace plslam
