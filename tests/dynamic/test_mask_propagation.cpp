// Instance masks carried from the segmented image to a later one: each instance follows its
// own motion, through the frames in between, an untextured one stays where it was, and one
// coming in at the border is filled in.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "dynamic/mask_propagation.h"
#include "eval/mask_overlap.h"

namespace plslam {
namespace {

const cv::Size kSize(320, 240);

// Blobs of several sizes, as real images have: Lucas-Kanade's coarse levels need the large ones.
cv::Mat noise(cv::Size size, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat sum(size, CV_32FC3, cv::Scalar::all(0));
  for (const int blob : {40, 12, 4}) {
    cv::Mat small(std::max(2, size.height / blob), std::max(2, size.width / blob), CV_32FC3), layer;
    rng.fill(small, cv::RNG::UNIFORM, 0, 85);
    cv::resize(small, layer, size, 0, 0, cv::INTER_CUBIC);
    sum += layer;
  }
  cv::Mat out;
  sum.convertTo(out, CV_8UC3);
  return out;
}

// A scene: a textured background and textured rectangles (the instances) at given places.
struct Scene {
  cv::Mat bgr;
  cv::Mat ids;  // CV_16U, k = rectangle k
};

// Rectangles may stick out of the image: only their part in view is drawn.
Scene draw(const std::vector<cv::Rect>& rects, bool textured = true) {
  Scene s{noise(kSize, 1), cv::Mat::zeros(kSize, CV_16UC1)};
  for (size_t k = 0; k < rects.size(); ++k) {
    const cv::Mat patch = textured ? noise(rects[k].size(), 10 + k) : cv::Mat(rects[k].size(), CV_8UC3, cv::Scalar(90, 90, 90));
    const cv::Rect in_view = rects[k] & cv::Rect(cv::Point(0, 0), kSize);
    patch(in_view - rects[k].tl()).copyTo(s.bgr(in_view));
    s.ids(in_view).setTo(cv::Scalar(static_cast<int>(k + 1)));
  }
  return s;
}

Segmentation segmentationOf(const Scene& s, const std::vector<cv::Rect>& rects) {
  Segmentation seg;
  seg.instance_ids = s.ids.clone();
  for (size_t k = 0; k < rects.size(); ++k) {
    Instance in;
    in.id = static_cast<int>(k + 1);
    in.box = rects[k] & cv::Rect(cv::Point(0, 0), kSize);
    seg.instances.push_back(in);
  }
  return seg;
}

double iou(const cv::Mat& a, const cv::Mat& b) {
  MaskOverlap o;
  o.add(a, b);
  return o.iou();
}

TEST(MaskPropagation, EachInstanceFollowsItsOwnMotion) {
  const std::vector<cv::Rect> before = {{40, 60, 60, 100}, {200, 50, 70, 90}};
  const std::vector<cv::Rect> after = {{58, 52, 60, 100}, {176, 60, 70, 90}};
  const Scene a = draw(before), b = draw(after);
  const MaskPropagationOptions o;
  const PropagationSource src = preparePropagation(segmentationOf(a, before), a.bgr, o);
  PropagationStats stats;
  const Segmentation moved = propagateSegmentation(src, propagationPyramid(b.bgr, o), o, &stats);
  EXPECT_EQ(stats.moved, 2);
  for (int k = 1; k <= 2; ++k) {
    const double carried = iou(moved.instance_ids == k, b.ids == k), stale = iou(a.ids == k, b.ids == k);
    EXPECT_GT(carried, 0.9) << "instance " << k;
    EXPECT_LT(stale, 0.7) << "instance " << k;
  }
  EXPECT_NEAR(moved.instances[0].box.x, after[0].x, 2);
  EXPECT_NEAR(moved.instances[1].box.y, after[1].y, 2);
}

TEST(MaskPropagation, AnInstanceWithoutCornersStaysWhereItWas) {
  const std::vector<cv::Rect> before = {{100, 60, 60, 100}};
  const Scene a = draw(before, false), b = draw({{112, 60, 60, 100}}, false);
  const MaskPropagationOptions o;
  PropagationStats stats;
  const Segmentation moved =
      propagateSegmentation(preparePropagation(segmentationOf(a, before), a.bgr, o), propagationPyramid(b.bgr, o), o, &stats);
  EXPECT_EQ(stats.kept, 1);
  EXPECT_EQ(cv::countNonZero(moved.instance_ids != a.ids), 0);
}

// A walker near the camera moves tens of pixels a frame: carried frame by frame through the
// images in between, its mask follows it much farther than a single step would.
TEST(MaskPropagation, TheCarrierFollowsAFastObjectThroughTheFramesInBetween) {
  const cv::Rect start(10, 40, 100, 160);
  const int step_px = 24, steps = 6;
  const Scene first = draw({start});
  MaskCarrier carrier;
  for (int i = 1; i <= steps; ++i) carrier.addFrame(i, draw({start + cv::Point(step_px * i, 0)}).bgr);
  carrier.setSource(preparePropagation(segmentationOf(first, {start}), first.bgr, {}), 0);
  PropagationStats stats;
  const Segmentation carried = carrier.carry(&stats);
  const Scene last = draw({start + cv::Point(step_px * steps, 0)});
  EXPECT_GT(iou(carried.instance_ids, last.ids), 0.9);
  ASSERT_EQ(stats.shifts.size(), 1u);
  EXPECT_NEAR(stats.shifts[0].x, step_px * steps, 2);
  // One more frame: only the new step is tracked, from where the corners were.
  carrier.addFrame(steps + 1, draw({start + cv::Point(step_px * (steps + 1), 0)}).bgr);
  EXPECT_GT(iou(carrier.carry().instance_ids, draw({start + cv::Point(step_px * (steps + 1), 0)}).ids), 0.9);
}

TEST(MaskPropagation, AnObjectComingInAtTheBorderIsFilledInFromIt) {
  // Half of the object is in view; 20 px more of it come in.
  const std::vector<cv::Rect> before = {{-60, 60, 120, 100}};
  const Scene a = draw(before), b = draw({{-40, 60, 120, 100}});
  const MaskPropagationOptions o;
  const Segmentation moved =
      propagateSegmentation(preparePropagation(segmentationOf(a, before), a.bgr, o), propagationPyramid(b.bgr, o), o);
  EXPECT_GT(iou(moved.instance_ids, b.ids), 0.9) << "the strip between the border and the moved pixels is the object's";
}

TEST(MaskPropagation, FeaturesAreAssignedToTheInteriorOfACarriedOutline) {
  const std::vector<cv::Rect> rects = {{40, 60, 60, 100}, {200, 50, 70, 90}};
  const Segmentation seg = segmentationOf(draw(rects), rects);
  PropagationStats stats;
  stats.shifts = {{0, 0}, {80, 0}};  // the second carried 80 px: its outline is uncertain
  const MaskPropagationOptions o;
  const cv::Mat interiors = carriedInteriors(seg, stats, o);
  EXPECT_EQ(cv::countNonZero(interiors == 1), 60 * 100) << "an instance that did not move keeps its outline";
  const int margin = static_cast<int>(o.interior_margin_fraction * 80);
  const cv::Rect inner(200 + margin, 50 + margin, 70 - 2 * margin, 90 - 2 * margin);
  EXPECT_NEAR(cv::countNonZero(interiors == 2), inner.area(), 0.05 * inner.area());
  EXPECT_EQ(cv::countNonZero(interiors(inner) != 2), 0);
}

}  // namespace
}  // namespace plslam
