// Precision and recall of DynamicFilter's rejection over a stretch of the synthetic dynamic
// scene, against the renderer's exact instance masks: a keypoint is truly dynamic when it
// lies on a walking person. Geometry only (no segmenter) and with replayed masks.
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "frontend/dynamic_filter.h"
#include "frontend/feature_extraction.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam {
namespace {

struct Confusion {
  int true_pos = 0, false_pos = 0, false_neg = 0, true_neg = 0;
  int band_kept = 0, band_rejected = 0;  // background keypoints on the silhouette band (not scored)
  // Where the errors come from (DynamicFrameResult::point_motion): a missed person keypoint
  // had no correspondence, or was judged still; a wrongly rejected one was flagged, or masked.
  int fn_unmatched = 0, fn_nodepth = 0, fn_still = 0, fp_flagged = 0, fp_masked = 0;
  double precision() const { return true_pos + false_pos ? double(true_pos) / (true_pos + false_pos) : 1.0; }
  double recall() const { return true_pos + false_neg ? double(true_pos) / (true_pos + false_neg) : 1.0; }
};

// A background keypoint this close to a person is a corner of the person's silhouette: its
// ORB patch (31 px) straddles the person and moves with it, so it is neither truly static
// nor truly dynamic. Such keypoints are counted apart, not scored.
constexpr float kSilhouetteBandPx = 8;

bool onPerson(const cv::Mat& ids, const Eigen::Vector2d& uv) {
  return ids.at<uint16_t>(cvRound(uv.y()), cvRound(uv.x())) != 0;
}

// The dynamic scene's masks replayed (its three walkers are persons), or none.
std::unique_ptr<Segmenter> testSegmenter(SegmenterKind kind) {
  if (kind != SegmenterKind::kReplay) return nullptr;
  SegmenterOptions so;
  so.kind = kind;
  so.replay_labels = {{1, 0, "person"}, {2, 0, "person"}, {3, 0, "person"}};
  return makeSegmenter(so);
}

// Frames [first, first + count) of the dynamic scene; the first compare_gap frames only
// prime the filter and are not scored.
Confusion scoreRejection(SegmenterKind kind, int first, int count) {
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic);
  const PinholeCamera& camera = scene.camera();
  DynamicFilterOptions o;
  DynamicFilter filter(camera, o, testSegmenter(kind), false);
  Confusion c;
  for (int i = first; i < first + count; ++i) {
    const synth::RenderedFrame r = synth::render(scene, i);
    const RgbdFrame frame = r.toRgbdFrame();
    FrameFeatures f = extractFeatures(frame, cv::Mat(), camera, FeatureOptions{});
    const std::vector<Keypoint> before = f.points;
    // The tracker's prior: constant velocity from the two previous (true) poses.
    std::optional<SE3> prior;
    if (i >= 2) prior = scene.cameraPose(i - 1).inverse() * scene.cameraPose(i - 2);
    const DynamicFrameResult res = filter.process(frame, &f, prior);
    EXPECT_EQ(res.point_motion.size(), before.size());
    EXPECT_EQ(res.point_kept.size(), before.size());
    if (res.point_motion.size() != before.size() || res.point_kept.size() != before.size()) return c;
    if (i < first + o.compare_gap) continue;
    cv::Mat dist;  // pixels to the nearest person pixel
    cv::distanceTransform(r.instance_ids == 0, dist, cv::DIST_L2, 3);
    for (const Keypoint& p : before) {
      const bool kept = res.point_kept[&p - before.data()];
      const bool truth = onPerson(r.instance_ids, p.uv_raw);
      const float d = dist.at<float>(cvRound(p.uv_raw.y()), cvRound(p.uv_raw.x()));
      const int8_t motion = res.point_motion[&p - before.data()];
      if (truth) {
        (kept ? c.false_neg : c.true_pos)++;
        if (kept) (motion < 0 ? c.fn_unmatched : c.fn_still)++;
        if (kept && motion < 0 && !std::isfinite(p.depth_m)) c.fn_nodepth++;
      } else if (d <= kSilhouetteBandPx) {
        (kept ? c.band_kept : c.band_rejected)++;
      } else {
        (kept ? c.true_neg : c.false_pos)++;
        if (!kept) (motion == 1 ? c.fp_flagged : c.fp_masked)++;
      }
    }
  }
  return c;
}

// Frames 170..229: the near person walks across most of the view.
constexpr int kFirst = 170, kCount = 60;

TEST(RejectionAccuracy, GeometryAloneRejectsMostPersonKeypointsAndFewBackgroundOnes) {
  const Confusion c = scoreRejection(SegmenterKind::kNone, kFirst, kCount);
  std::printf("geometry only: precision %.3f recall %.3f (tp %d fp %d fn %d tn %d)\n", c.precision(), c.recall(),
              c.true_pos, c.false_pos, c.false_neg, c.true_neg);
  std::printf("silhouette band (not scored): %d rejected, %d kept\n", c.band_rejected, c.band_kept);
  std::printf("missed: %d unjudged (%d without depth), %d judged still; wrongly rejected: %d flagged, %d masked\n",
              c.fn_unmatched, c.fn_nodepth, c.fn_still, c.fp_flagged, c.fp_masked);
  ASSERT_GT(c.true_pos + c.false_neg, 200) << "persons must be in view for this test to mean anything";
  // Issue 4's figures. Measured 0.850 / 0.902 (before label spreading and the 0.7 match ratio:
  // 0.61 / 0.72, nearly every miss a keypoint without a correspondence).
  EXPECT_GE(c.recall(), 0.8);
  EXPECT_GE(c.precision(), 0.9);
}

TEST(RejectionAccuracy, ReplayedMasksRejectNearlyEveryPersonKeypoint) {
  const Confusion c = scoreRejection(SegmenterKind::kReplay, kFirst, kCount);
  std::printf("replayed masks: precision %.3f recall %.3f (tp %d fp %d fn %d tn %d)\n", c.precision(), c.recall(),
              c.true_pos, c.false_pos, c.false_neg, c.true_neg);
  std::printf("silhouette band (not scored): %d rejected, %d kept\n", c.band_rejected, c.band_kept);
  // Measured 0.953 / 0.872: masks up to two frames old miss the person's leading edge and
  // still cover where it was (0.979 / 0.870 when labels were also spread on masked frames,
  // which cost fr3_sitting_static 0.0100 against 0.0084 m ATE).
  EXPECT_GE(c.recall(), 0.95);
  EXPECT_GE(c.precision(), 0.85);
}

// Keypoints the geometric labels reach (judged still or moving) over frames of the dynamic
// scene: label spreading gives unmatched keypoints their neighbours' verdict.
int judgedKeypoints(SegmenterKind kind, bool spread_with_masks) {
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic);
  DynamicFilterOptions o;
  o.spread_with_masks = spread_with_masks;
  DynamicFilter filter(scene.camera(), o, testSegmenter(kind), false);
  int judged = 0;
  for (int i = kFirst; i < kFirst + 12; ++i) {
    const RgbdFrame frame = synth::render(scene, i).toRgbdFrame();
    FrameFeatures f = extractFeatures(frame, cv::Mat(), scene.camera(), FeatureOptions{});
    const DynamicFrameResult res = filter.process(frame, &f, scene.cameraPose(i - 1).inverse() * scene.cameraPose(i - 2));
    for (int8_t m : res.point_motion) judged += m >= 0;
  }
  return judged;
}

TEST(RejectionAccuracy, LabelsSpreadOnlyOnFramesWithoutMasksUnlessAskedTo) {
  const int geometry = judgedKeypoints(SegmenterKind::kNone, false);
  const int masks = judgedKeypoints(SegmenterKind::kReplay, false);
  const int masks_spread = judgedKeypoints(SegmenterKind::kReplay, true);
  std::printf("judged keypoints: geometry only %d, masks %d, masks with spreading %d\n", geometry, masks, masks_spread);
  // The labels, before masks apply, do not depend on the masks except through spreading.
  EXPECT_EQ(masks_spread, geometry);
  EXPECT_LT(masks, geometry * 0.9) << "with masks, unmatched keypoints must stay unjudged";
}

}  // namespace
}  // namespace plslam
