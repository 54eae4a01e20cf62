// The motion check, the Delaunay graph and the fused mask on rendered frames of the synthetic
// `dynamic` scene: ORB correspondences between two adjacent frames with depth, instance masks
// from the renderer, ground truth from the scene.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "dynamic/delaunay_motion.h"
#include "dynamic/dynamic_mask.h"
#include "dynamic/motion_check.h"
#include "synth/renderer.h"
#include "synth/scene.h"

using namespace plslam;

namespace {

struct SceneStep {
  synth::RenderedFrame prev, cur;
  std::vector<MotionCorrespondence> corr;
  std::vector<int> instance;  // ground truth: the instance id under each current feature (0: static)
  Segmentation seg;           // from the renderer's instance ids (persons)
  MotionCheckResult motion;
  DelaunayMotionResult delaunay;
  DynamicMaskResult mask;
};

/// ORB features matched between frames i and i+1 (brute force, cross-checked), with depth.
std::vector<MotionCorrespondence> orbCorrespondences(const synth::Scene& scene, const synth::RenderedFrame& a,
                                                     const synth::RenderedFrame& b) {
  const auto orb = cv::ORB::create(1000);
  cv::Mat ga, gb, da, db;
  std::vector<cv::KeyPoint> ka, kb;
  cv::cvtColor(a.bgr, ga, cv::COLOR_BGR2GRAY);
  cv::cvtColor(b.bgr, gb, cv::COLOR_BGR2GRAY);
  orb->detectAndCompute(ga, cv::noArray(), ka, da);
  orb->detectAndCompute(gb, cv::noArray(), kb, db);
  std::vector<cv::DMatch> matches;
  cv::BFMatcher(cv::NORM_HAMMING, true).match(da, db, matches);
  const PinholeCamera& cam = scene.camera();  // no distortion: keypoints are ideal pixels
  std::vector<MotionCorrespondence> out;
  for (const auto& m : matches) {
    if (m.distance > 50) continue;
    const cv::KeyPoint& p = ka[m.queryIdx];
    const cv::KeyPoint& q = kb[m.trainIdx];
    MotionCorrespondence c;
    c.uv_prev = Eigen::Vector2d(p.pt.x, p.pt.y);
    c.uv_cur = Eigen::Vector2d(q.pt.x, q.pt.y);
    const double za = depthAt(a.depth_m, p.pt.x, p.pt.y), zb = depthAt(b.depth_m, q.pt.x, q.pt.y);
    if (std::isfinite(za) && za > 0) c.p_prev = cam.unprojectIdeal(c.uv_prev, za);
    if (std::isfinite(zb) && zb > 0) c.p_cur = cam.unprojectIdeal(c.uv_cur, zb);
    c.pixel_sigma_scale = std::pow(1.2, std::max(p.octave, q.octave));
    out.push_back(c);
  }
  return out;
}

Segmentation personsOf(const synth::RenderedFrame& f) {
  Segmentation s;
  s.t_ns = f.t_ns;
  s.instance_ids = f.instance_ids.clone();
  double max_id = 0;
  cv::minMaxLoc(f.instance_ids, nullptr, &max_id);
  for (int id = 1; id <= static_cast<int>(max_id); ++id) {
    const cv::Mat pixels = f.instance_ids == id;
    if (cv::countNonZero(pixels) == 0) continue;
    Instance inst;
    inst.id = id;
    inst.class_id = 0;
    inst.class_name = "person";
    inst.box = cv::boundingRect(pixels);
    inst.potentially_dynamic = true;
    s.instances.push_back(inst);
  }
  return s;
}

/// Frames i - gap + 1 (previous) and i + 1 (current).
SceneStep runStep(const synth::Scene& scene, int i, int gap = 1) {
  SceneStep s;
  s.prev = synth::render(scene, i + 1 - gap);
  s.cur = synth::render(scene, i + 1);
  s.corr = orbCorrespondences(scene, s.prev, s.cur);
  for (const auto& c : s.corr)
    s.instance.push_back(s.cur.instance_ids.at<uint16_t>(cvRound(c.uv_cur.y()), cvRound(c.uv_cur.x())));
  s.seg = personsOf(s.cur);
  s.motion = checkMotion(s.corr, scene.camera());
  s.delaunay = analyseDelaunayMotion(s.corr, scene.camera(), {}, &s.motion);
  s.mask = fuseDynamicMask({&s.corr, &s.motion, &s.delaunay, &s.seg}, s.cur.depth_m.size());
  return s;
}

synth::SceneOptions exactDepth() {
  synth::SceneOptions o;
  o.noise.enabled = false;
  return o;
}

}  // namespace

TEST(MotionScene, WalkingPersonIsMaskedAndBackgroundKept) {
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, exactDepth());
  // Frame 200: the near person covers about a fifth of the image, walking across it.
  const SceneStep s = runStep(scene, 200);
  ASSERT_EQ(s.motion.status, MotionCheckStatus::kOk) << motionCheckStatusName(s.motion.status);
  const SE3 truth = s.cur.T_w_c.inverse() * s.prev.T_w_c;
  EXPECT_LT((s.motion.T_cur_prev.translation() - truth.translation()).norm(), 0.005);
  EXPECT_LT((s.motion.T_cur_prev * truth.inverse()).angle() * 180 / M_PI, 0.2);

  // The person is judged moving by the geometry (not by its class), and masked whole.
  ASSERT_FALSE(s.seg.instances.empty());
  bool near_person = false;
  for (const auto& d : s.mask.instances) {
    EXPECT_TRUE(d.dynamic) << "instance " << d.instance_id << " " << instanceDecisionReasonName(d.reason);
    if (d.instance_id == 1) {
      near_person = true;
      EXPECT_EQ(d.reason, InstanceDecisionReason::kMovingByGeometry) << d.moving << "/" << d.checked;
    }
  }
  EXPECT_TRUE(near_person);
  const cv::Mat person = s.cur.instance_ids > 0, background = s.cur.instance_ids == 0;
  ASSERT_GT(cv::countNonZero(person), 0.1 * person.total());
  EXPECT_EQ(cv::countNonZero(s.mask.mask & person), 0);
  const double kept = static_cast<double>(cv::countNonZero(s.mask.mask & background)) / cv::countNonZero(background);
  EXPECT_GE(kept, 0.95);

  // Features: all on the person rejected; of the background, the true correspondences kept
  // and the wrong ones (ORB mismatches, depth taken across a depth edge) mostly rejected.
  int good = 0, good_rejected = 0, wrong = 0, wrong_rejected = 0;
  for (size_t i = 0; i < s.corr.size(); ++i) {
    if (s.instance[i] != 0) {
      EXPECT_TRUE(s.mask.feature_dynamic[i]) << "person feature " << i;
      continue;
    }
    const auto& c = s.corr[i];
    if (!c.hasDepthPrev() || !c.hasDepthCur()) continue;
    const Eigen::Vector3d q = truth * c.p_prev;
    const bool correct = (scene.camera().projectIdeal(q) - c.uv_cur).norm() < 2.0 * c.pixel_sigma_scale &&
                         std::abs(q.z() - c.p_cur.z()) < 0.02 + 0.01 * q.z();
    (correct ? good : wrong)++;
    (correct ? good_rejected : wrong_rejected) += s.mask.feature_dynamic[i];
  }
  ASSERT_GT(good, 100);
  EXPECT_LT(good_rejected, 0.05 * good);
  if (wrong >= 5) {
    EXPECT_GT(wrong_rejected, 0.7 * wrong) << wrong_rejected << " of " << wrong;
  }
}

TEST(MotionScene, GeometryAloneFindsThePersonWithoutSegmentation) {
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, exactDepth());
  SceneStep s = runStep(scene, 200);
  // No segmenter: the Delaunay regions carry the person.
  s.mask = fuseDynamicMask({&s.corr, &s.motion, &s.delaunay, nullptr}, s.cur.depth_m.size());
  ASSERT_GE(s.mask.stats.regions_dynamic, 1);
  int person_features = 0, person_in_regions = 0;
  std::vector<uint8_t> in_region(s.corr.size(), 0);
  for (size_t r = 0; r < s.delaunay.regions.size(); ++r)
    if (s.mask.regions[r].dynamic)
      for (int i : s.delaunay.regions[r].features) in_region[i] = 1;
  for (size_t i = 0; i < s.corr.size(); ++i) {
    if (s.instance[i] != 1 || !s.delaunay.in_graph[i]) continue;
    ++person_features;
    person_in_regions += in_region[i];
  }
  ASSERT_GT(person_features, 10);
  EXPECT_GT(person_in_regions, 0.8 * person_features);
  const cv::Mat background = s.cur.instance_ids == 0;
  const double kept = static_cast<double>(cv::countNonZero(s.mask.mask & background)) / cv::countNonZero(background);
  EXPECT_GE(kept, 0.95);
}

TEST(MotionScene, ThreeFrameBaselineCatchesASlowWalkerUnderNoise) {
  // Frames 228..231: the near person turns at the end of its path (about 0.3 m/s); with
  // Kinect-like noise one frame of motion hides in the noise, three frames do not.
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, synth::SceneOptions{});
  const SceneStep s = runStep(scene, 230, 3);
  ASSERT_EQ(s.motion.status, MotionCheckStatus::kOk);
  const SE3 truth = s.cur.T_w_c.inverse() * s.prev.T_w_c;
  EXPECT_LT((s.motion.T_cur_prev.translation() - truth.translation()).norm(), 0.01);
  ASSERT_FALSE(s.mask.instances.empty());
  const InstanceDecision& d = s.mask.instances.front();
  EXPECT_EQ(d.instance_id, 1);
  EXPECT_EQ(d.reason, InstanceDecisionReason::kMovingByGeometry) << d.moving << "/" << d.checked;
  const cv::Mat person = s.cur.instance_ids > 0, background = s.cur.instance_ids == 0;
  EXPECT_EQ(cv::countNonZero(s.mask.mask & person), 0);
  EXPECT_GE(static_cast<double>(cv::countNonZero(s.mask.mask & background)) / cv::countNonZero(background), 0.95);
}
