#include "features/lbd.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/line_descriptor.hpp>
#include <random>

#include "core/error.h"

namespace plslam {
namespace {

// A smooth random texture with some edges, so that the gradients have structure at every scale.
cv::Mat texturedImage(std::mt19937* rng, int width, int height) {
  cv::Mat noise(height / 8, width / 8, CV_8U);
  cv::randu(noise, 0, 256);
  cv::Mat image;
  cv::resize(noise, image, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  std::uniform_int_distribution<int> x(0, width - 1), y(0, height - 1), grey(0, 255);
  for (int i = 0; i < 20; ++i)
    cv::line(image, {x(*rng), y(*rng)}, {x(*rng), y(*rng)}, cv::Scalar(grey(*rng)), 2);
  return image;
}

// Segments anywhere, some reaching past the border (the support region is then clamped).
std::vector<LbdSegment> randomSegments(std::mt19937* rng, int width, int height, int count) {
  std::uniform_real_distribution<float> x(-10.f, width + 10.f), y(-10.f, height + 10.f);
  std::vector<LbdSegment> segments;
  while (static_cast<int>(segments.size()) < count) {
    LbdSegment s;
    s.start_x = x(*rng), s.start_y = y(*rng), s.end_x = x(*rng), s.end_y = y(*rng);
    const float length = std::hypot(s.end_x - s.start_x, s.end_y - s.start_y);
    if (length < 3) continue;
    s.angle = std::atan2(s.end_y - s.start_y, s.end_x - s.start_x);
    s.samples = static_cast<int>(std::lround(length));
    segments.push_back(s);
  }
  return segments;
}

cv::Mat opencvLbd(const cv::Mat& image, const std::vector<LbdSegment>& segments) {
  std::vector<cv::line_descriptor::KeyLine> keylines;
  for (size_t i = 0; i < segments.size(); ++i) {
    const LbdSegment& s = segments[i];
    cv::line_descriptor::KeyLine k;
    k.startPointX = k.sPointInOctaveX = s.start_x;
    k.startPointY = k.sPointInOctaveY = s.start_y;
    k.endPointX = k.ePointInOctaveX = s.end_x;
    k.endPointY = k.ePointInOctaveY = s.end_y;
    k.lineLength = std::hypot(s.end_x - s.start_x, s.end_y - s.start_y);
    k.numOfPixels = s.samples;
    k.angle = s.angle;
    k.octave = 0;
    k.class_id = static_cast<int>(i);
    keylines.push_back(k);
  }
  cv::line_descriptor::BinaryDescriptor::Params params;
  params.numOfOctave_ = 1;
  cv::Mat descriptors;
  cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor(params)->compute(image, keylines, descriptors);
  return descriptors;
}

TEST(Lbd, GivesOpenCvsBitsOnRandomImagesAndSegments) {
  std::mt19937 rng(7);
  int segments_compared = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const cv::Mat image = texturedImage(&rng, 320, 240);
    const std::vector<LbdSegment> segments = randomSegments(&rng, 320, 240, 150);
    const cv::Mat ours = describeLbd(image, segments), theirs = opencvLbd(image, segments);
    ASSERT_EQ(ours.rows, theirs.rows);
    ASSERT_EQ(ours.cols, 32);
    for (int i = 0; i < ours.rows; ++i, ++segments_compared)
      EXPECT_EQ(cv::norm(ours.row(i), theirs.row(i), cv::NORM_HAMMING), 0) << "trial " << trial << " segment " << i;
  }
  EXPECT_EQ(segments_compared, 8 * 150);
}

TEST(Lbd, AnEmptyListGivesNoRowsAndAColourOrEmptyImageOrAnEmptySegmentIsRefused) {
  const cv::Mat grey(48, 64, CV_8U, cv::Scalar(128));
  const cv::Mat none = describeLbd(grey, {});
  EXPECT_EQ(none.rows, 0);
  EXPECT_EQ(none.cols, 32);
  EXPECT_THROW(describeLbd(cv::Mat(48, 64, CV_8UC3), {LbdSegment{}}), std::exception);
  EXPECT_THROW(describeLbd(cv::Mat(0, 0, CV_8U), {LbdSegment{}}), Error);
  LbdSegment empty;
  empty.samples = 0;
  EXPECT_THROW(describeLbd(grey, {empty}), std::exception);
}

}  // namespace
}  // namespace plslam
