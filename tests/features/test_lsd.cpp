#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "features/lsd.h"
#include "synthetic_images.h"

namespace plslam {
namespace {

// Both endpoints of `a` within `tolerance` of those of `b`, in the same order (same polarity).
bool sameSegment(const cv::Vec4f& a, const cv::Vec4f& b, double tolerance) {
  return std::hypot(a[0] - b[0], a[1] - b[1]) <= tolerance && std::hypot(a[2] - b[2], a[3] - b[3]) <= tolerance;
}

double length(const cv::Vec4f& s) { return std::hypot(s[2] - s[0], s[3] - s[1]); }

// The share of `from`'s segments longer than `min_length` that have a counterpart in `in`.
double shareFound(const std::vector<cv::Vec4f>& from, const std::vector<cv::Vec4f>& in, double min_length) {
  int total = 0, found = 0;
  for (const cv::Vec4f& s : from) {
    if (length(s) < min_length) continue;
    ++total;
    for (const cv::Vec4f& t : in)
      if (sameSegment(s, t, 1.0)) {
        ++found;
        break;
      }
  }
  return total ? double(found) / total : 1.0;
}

// A drawn image with sensor-like noise: flat-colour drawings have many gradients of exactly
// equal norm, whose order OpenCV leaves to its sort.
cv::Mat withNoise(const cv::Mat& img, uint64_t seed) {
  cv::Mat noise(img.size(), CV_16S), noisy;
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0, 3);
  cv::add(img, noise, noisy, cv::noArray(), CV_8U);
  return noisy;
}

TEST(Lsd, FindsTheSegmentsOpenCvsLsdFinds) {
  // The same detector as OpenCV's LSD without refinement, on images full of edges and
  // corners. Seeds of equal gradient bins are taken in another order, so a few regions
  // differ (taken in OpenCV's order, all segments came out the same within 0.01 px).
  int compared = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed)
    for (const cv::Mat& drawn : {test::structureImage({640, 480}, seed), test::blobImage({640, 480}, seed)})
      for (double scale : {0.5, 1.0}) {
        const cv::Mat img = withNoise(drawn, seed);
        std::vector<cv::Vec4f> reference;
        cv::createLineSegmentDetector(cv::LSD_REFINE_NONE, scale, 0.6, 2.0)->detect(img, reference);
        LsdParameters p;
        p.scale = scale;
        const std::vector<cv::Vec4f> ours = detectLsdSegments(img, p);
        ASSERT_GT(reference.size(), 30u);
        EXPECT_GT(shareFound(reference, ours, 10), 0.95) << "seed " << seed << " scale " << scale;
        EXPECT_GT(shareFound(ours, reference, 10), 0.95) << "seed " << seed << " scale " << scale;
        EXPECT_NEAR(double(ours.size()), double(reference.size()), 0.05 * reference.size());
        ++compared;
      }
  EXPECT_EQ(compared, 12);
}

TEST(Lsd, FindsEachSideOfARectangleWhereItIs) {
  // A dark rectangle over pixels 80..239 x 60..179 on a bright background: its sides lie
  // half a pixel outside those (79.5, 239.5, 59.5, 179.5), each found whole, darker side on
  // the right.
  cv::Mat img(240, 320, CV_8U, cv::Scalar(200));
  cv::rectangle(img, cv::Rect(80, 60, 160, 120), cv::Scalar(40), cv::FILLED);
  LsdParameters p;
  p.scale = 1.0;
  const std::vector<cv::Vec4f> segments = detectLsdSegments(img, p);
  const std::vector<cv::Vec4f> sides = {{79.5f, 179.5f, 79.5f, 59.5f},     // left: going up
                                        {239.5f, 179.5f, 79.5f, 179.5f},   // bottom: going left
                                        {239.5f, 59.5f, 239.5f, 179.5f},   // right: going down
                                        {79.5f, 59.5f, 239.5f, 59.5f}};    // top: going right
  for (const cv::Vec4f& side : sides) {
    int found = 0;
    for (const cv::Vec4f& s : segments) found += sameSegment(s, side, 2.0);
    EXPECT_EQ(found, 1) << "side " << side;
  }
  for (const cv::Vec4f& s : segments) EXPECT_GT(length(s), 100) << s;  // nothing but the four sides
  EXPECT_EQ(segments.size(), 4u);
}

TEST(Lsd, AnImageWithoutEdgesHasNoSegment) {
  EXPECT_TRUE(detectLsdSegments(cv::Mat(240, 320, CV_8U, cv::Scalar(128)), LsdParameters()).empty());
  // A ramp of one grey level every 4 pixels: its gradient is under the threshold everywhere.
  cv::Mat ramp(240, 320, CV_8U);
  for (int x = 0; x < ramp.cols; ++x) ramp.col(x).setTo(x / 4);
  EXPECT_TRUE(detectLsdSegments(ramp, LsdParameters()).empty());
  EXPECT_TRUE(detectLsdSegments(cv::Mat(), LsdParameters()).empty());
  // Too small for a 2 x 2 gradient once sub-sampled: nothing, not an OpenCV assertion.
  LsdParameters half;
  half.scale = 0.5;
  for (int side : {1, 2, 3}) EXPECT_TRUE(detectLsdSegments(cv::Mat(side, side, CV_8U, cv::Scalar(7)), half).empty());
}

TEST(Lsd, RefusesAColourImageAndParametersOutOfRange) {
  EXPECT_THROW(detectLsdSegments(cv::Mat(240, 320, CV_8UC3, cv::Scalar::all(0)), LsdParameters()), DataError);
  const cv::Mat grey(240, 320, CV_8U, cv::Scalar(0));
  for (auto breaks : {+[](LsdParameters* p) { p->scale = 0; }, +[](LsdParameters* p) { p->scale = 1.5; },
                      +[](LsdParameters* p) { p->sigma_scale = 0; }, +[](LsdParameters* p) { p->quant = -1; },
                      +[](LsdParameters* p) { p->angle_tol_deg = 180; }, +[](LsdParameters* p) { p->bins = 0; }}) {
    LsdParameters p;
    breaks(&p);
    EXPECT_THROW(detectLsdSegments(grey, p), ConfigError);
  }
}

}  // namespace
}  // namespace plslam
