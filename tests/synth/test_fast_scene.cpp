// The fast-motion scene (issue 17): a hand-held path with bursts near 180 deg/s after a
// slow first second, motion blur along the image motion, a varying exposure gain, and
// ground truth at the stamps (the middle of each exposure).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "io/trajectory_file.h"
#include "support/test_support.h"
#include "synth/dataset.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace fs = std::filesystem;
using namespace plslam;
using namespace plslam::synth;

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

SceneOptions small(int width = 320, int height = 240) {
  SceneOptions o;
  o.width = width;
  o.height = height;
  o.noise.enabled = false;
  return o;
}

/// Angular rate (deg/s) and speed (m/s) of the camera between t and t + dt.
std::pair<double, double> ratesAt(const Scene& s, TimeNs t, TimeNs dt) {
  const SE3 d = s.cameraPoseAt(t).inverse() * s.cameraPoseAt(t + dt);
  return {d.angle() / nsToSeconds(dt) * kRadToDeg, d.translation().norm() / nsToSeconds(dt)};
}

/// The frame of the highest angular rate at the stamp.
int fastestFrame(const Scene& s) {
  int best = 0;
  double best_rate = -1;
  for (int i = 0; i < s.frameCount(); ++i) {
    const double r = ratesAt(s, s.frameTime(i) - 500'000, 1'000'000).first;
    if (r > best_rate) best_rate = r, best = i;
  }
  return best;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

cv::Mat greyFloat(const cv::Mat& bgr) {
  cv::Mat g, f;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  g.convertTo(f, CV_32F);
  return f;
}

/// Gradient energy along and across the image motion predicted at each pixel (from its
/// exact depth and the poses at the start and end of the exposure).
std::pair<double, double> energyAlongAcross(const Scene& s, const RenderedFrame& f, const cv::Mat& grey) {
  cv::Mat gx, gy;
  cv::Sobel(grey, gx, CV_32F, 1, 0);
  cv::Sobel(grey, gy, CV_32F, 0, 1);
  const PinholeCamera& cam = s.camera();
  const TimeNs half = s.exposureNs() / 2;
  const SE3 T_0_c = s.cameraPoseAt(f.t_ns - half).inverse() * f.T_w_c;
  const SE3 T_1_c = s.cameraPoseAt(f.t_ns + half).inverse() * f.T_w_c;
  double along = 0, across = 0;
  for (int y = 2; y < grey.rows - 2; ++y)
    for (int x = 2; x < grey.cols - 2; ++x) {
      const float z = f.depth_m.at<float>(y, x);
      if (!std::isfinite(z)) continue;
      const Eigen::Vector3d p = cam.unprojectIdeal(Eigen::Vector2d(x, y), z);
      const Eigen::Vector3d a = T_0_c * p, b = T_1_c * p;
      Eigen::Vector2d flow(cam.fx * (b.x() / b.z() - a.x() / a.z()), cam.fy * (b.y() / b.z() - a.y() / a.z()));
      if (flow.norm() < 1.0) continue;
      flow.normalize();
      const double g0 = gx.at<float>(y, x), g1 = gy.at<float>(y, x);
      along += std::pow(g0 * flow.x() + g1 * flow.y(), 2);
      across += std::pow(-g0 * flow.y() + g1 * flow.x(), 2);
    }
  return {along, across};
}

double meanAbsDiff(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_L1) / a.total(); }

}  // namespace

TEST(SynthFastScene, PathPeaksNear180DegPerSecondAfterASlowFirstSecond) {
  const Scene s = makeScene(SceneKind::kFast, small());
  ASSERT_EQ(s.frameCount(), defaultFrameCount(SceneKind::kFast));
  const TimeNs dt = 1'000'000;  // 1 ms: the exact rates, not 30 Hz averages
  double peak_w = 0, peak_v = 0, first_w = 0, first_v = 0, fast_s = 0, worst_jump = 0;
  SE3 prev_step;
  for (TimeNs t = s.frameTime(0); t < s.frameTime(s.frameCount() - 1); t += dt) {
    const auto [w, v] = ratesAt(s, t, dt);
    peak_w = std::max(peak_w, w), peak_v = std::max(peak_v, v);
    if (t < s.frameTime(30)) first_w = std::max(first_w, w), first_v = std::max(first_v, v);
    if (w > 90) fast_s += nsToSeconds(dt);
    // Smooth: the angular velocity (body twist) changes little from one millisecond to the next.
    const SE3 step = s.cameraPoseAt(t).inverse() * s.cameraPoseAt(t + dt);
    if (t > s.frameTime(0)) worst_jump = std::max(worst_jump, (step.log() - prev_step.log()).tail<3>().norm() / nsToSeconds(dt));
    prev_step = step;
  }
  EXPECT_GE(peak_w, 150);
  EXPECT_LE(peak_w, 200);
  EXPECT_GT(peak_v, 0.6) << "bursts should translate fast too";
  EXPECT_LT(peak_v, 1.3);
  EXPECT_LT(first_w, 20) << "the first second is for initialisation";
  EXPECT_LT(first_v, 0.15);
  EXPECT_GT(fast_s, 1.0) << "seconds above 90 deg/s: several bursts";
  EXPECT_LT(fast_s, 5.0) << "calm stretches between the bursts";
  EXPECT_LT(worst_jump, 0.05) << "angular velocity jumps (rad/s per ms): the path is not smooth";
  // The knob scales the bursts.
  SceneOptions slow = small();
  slow.fast.max_rotation_deg_s = 90;
  const Scene s90 = makeScene(SceneKind::kFast, slow);
  double peak90 = 0;
  for (TimeNs t = s90.frameTime(0); t < s90.frameTime(s90.frameCount() - 1); t += dt)
    peak90 = std::max(peak90, ratesAt(s90, t, dt).first);
  EXPECT_GE(peak90, 75);
  EXPECT_LE(peak90, 100);
}

TEST(SynthFastScene, CameraKeepsTexturedFurnitureInViewAtUsefulRange) {
  const Scene s = makeScene(SceneKind::kFast, small());
  const Trajectory gt = s.groundTruth();
  for (size_t i = 0; i < gt.size(); i += 3) {
    const Eigen::Vector3d c = gt[i].T_w_c.translation();
    const RayHit hit = castRay(s.staticBoxes(), c, gt[i].T_w_c.quaternion() * Eigen::Vector3d::UnitZ());
    ASSERT_TRUE(hit.hit);
    EXPECT_GT(hit.distance, 1.0) << "frame " << i;
    EXPECT_LT(hit.distance, 5.0) << "frame " << i;
    EXPECT_GT(s.staticSurfaceDistance(c), 0.5) << "frame " << i;
  }
  // Sharp frames across the sequence have plenty of corners for the tracker.
  SceneOptions o = small();
  o.fast.motion_blur = false;
  const Scene sharp = makeScene(SceneKind::kFast, o);
  for (int frame = 15; frame < sharp.frameCount(); frame += 45) {
    cv::Mat grey;
    cv::cvtColor(render(sharp, frame).bgr, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> kp;
    cv::ORB::create(500)->detect(grey, kp);
    EXPECT_GE(kp.size(), 250u) << "frame " << frame;
  }
}

TEST(SynthFastScene, MotionBlurRunsAlongThePredictedImageMotion) {
  const Scene blurred = makeScene(SceneKind::kFast, small());
  SceneOptions o = small();
  o.fast.motion_blur = false;
  const Scene sharp = makeScene(SceneKind::kFast, o);
  const int i = fastestFrame(blurred);
  const RenderedFrame b = render(blurred, i), a = render(sharp, i);
  // 180 deg/s over 12 ms at f = 262 px: about 10 px of motion, 1.5 px per sub-frame.
  EXPECT_GE(b.subframes, 6);
  EXPECT_LE(b.subframes, blurred.options().fast.max_subframes);
  EXPECT_EQ(a.subframes, 1);
  const auto [a_along, a_across] = energyAlongAcross(blurred, a, greyFloat(a.bgr));
  const auto [b_along, b_across] = energyAlongAcross(blurred, b, greyFloat(b.bgr));
  // Blur removes the gradients along the motion, much less those across it.
  EXPECT_LT(b_along / a_along, 0.35);
  EXPECT_LT(b_along / b_across, 0.4 * (a_along / a_across));
  EXPECT_GT(b_across / a_across, 2.0 * b_along / a_along);
  // A calm frame of the first second is barely blurred.
  EXPECT_LE(render(blurred, 10).subframes, 2);
}

TEST(SynthFastScene, WithBlurOffAFrameIsTheSingleShotRender) {
  SceneOptions o = small();
  o.noise.enabled = true;  // the same noise stream either way
  const Scene blurred = makeScene(SceneKind::kFast, o);
  o.fast.motion_blur = false;
  const Scene sharp = makeScene(SceneKind::kFast, o);
  const int i = fastestFrame(sharp);
  const RenderedFrame single = renderView(sharp, sharp.cameraPose(i), sharp.frameTime(i), i);
  const RenderedFrame off = render(sharp, i), on = render(blurred, i);
  EXPECT_TRUE(sameBytes(off.bgr, single.bgr));
  EXPECT_TRUE(sameBytes(off.depth_m, single.depth_m));
  EXPECT_GT(meanAbsDiff(on.bgr, off.bgr), 3.0) << "blur on should change a fast frame";
  EXPECT_TRUE(sameBytes(on.depth_m, off.depth_m)) << "depth is taken at the stamp, blur or not";
  EXPECT_TRUE(sameBytes(on.instance_ids, off.instance_ids));
}

TEST(SynthFastScene, GainScalesTheMeanIntensityByTheExpectedFactor) {
  SceneOptions o = small(160, 120);
  o.fast.motion_blur = false;
  const Scene s = makeScene(SceneKind::kFast, o);
  double lo = 9, hi = 0, fastest_change = 0;
  int far_frame = 0;
  for (int i = 0; i < s.frameCount(); ++i) {
    const double g = s.exposureGain(s.frameTime(i));
    lo = std::min(lo, g), hi = std::max(hi, g);
    if (std::abs(g - 1) > std::abs(s.exposureGain(s.frameTime(far_frame)) - 1)) far_frame = i;
    if (i >= 6) fastest_change = std::max(fastest_change, std::abs(g - s.exposureGain(s.frameTime(i - 6))));
  }
  EXPECT_GE(lo, 0.6);
  EXPECT_LE(hi, 1.4);
  EXPECT_LT(lo, 0.85);
  EXPECT_GT(hi, 1.15);
  EXPECT_GT(fastest_change, 0.15) << "an auto-exposure-like step within 0.2 s";

  const double g = s.exposureGain(s.frameTime(far_frame));
  o.fast.gain = false;
  const Scene flat = makeScene(SceneKind::kFast, o);
  EXPECT_EQ(flat.exposureGain(s.frameTime(far_frame)), 1.0);
  cv::Mat with, without;
  cv::cvtColor(render(s, far_frame).bgr, with, cv::COLOR_BGR2GRAY);
  cv::cvtColor(render(flat, far_frame).bgr, without, cv::COLOR_BGR2GRAY);
  // Means over the pixels the gain did not saturate.
  const cv::Mat unsaturated = without * std::max(g, 1.0) < 250;
  const double ratio = cv::mean(with, unsaturated)[0] / cv::mean(without, unsaturated)[0];
  EXPECT_NEAR(ratio, g, 0.01 * g) << "frame " << far_frame;

  o.seed = 2;
  o.fast.gain = true;
  const Scene other = makeScene(SceneKind::kFast, o);
  EXPECT_NE(other.exposureGain(s.frameTime(far_frame)), g) << "the seed sets the gain's course";
  EXPECT_EQ(makeScene(SceneKind::kStatic, o).exposureGain(s.frameTime(far_frame)), 1.0);
}

TEST(SynthFastScene, GroundTruthIsThePoseAtTheStampInTheMiddleOfTheExposure) {
  SceneOptions o = small(160, 120);
  const Scene s = makeScene(SceneKind::kFast, o);
  const int i = fastestFrame(s);
  const RenderedFrame f = render(s, i);
  EXPECT_EQ(f.t_ns, s.frameTime(i));
  EXPECT_LT((f.T_w_c.inverse() * s.cameraPoseAt(f.t_ns)).log().norm(), 1e-12);
  // The blurred colour is centred on the stamp: the sharp view at the stamp is closer to it
  // than the sharp views at the start and the end of the exposure.
  const TimeNs half = s.exposureNs() / 2;
  ASSERT_GT(half, 0);
  auto sharpAt = [&](TimeNs t) { return renderView(s, s.cameraPoseAt(t), t, i).bgr; };
  const double mid = meanAbsDiff(f.bgr, sharpAt(f.t_ns));
  EXPECT_LT(mid, 0.8 * meanAbsDiff(f.bgr, sharpAt(f.t_ns - half)));
  EXPECT_LT(mid, 0.8 * meanAbsDiff(f.bgr, sharpAt(f.t_ns + half)));

  // groundtruth.txt holds the poses at the colour (and depth) stamps.
  o.frames = 3;
  o.width = 64;
  o.height = 48;
  const Scene tiny = makeScene(SceneKind::kFast, o);
  const std::string dir = test::scratchDir("synth_fast_dataset");
  writeDataset(tiny, dir);
  const Trajectory gt = readTumTrajectory(dir + "/groundtruth.txt");
  ASSERT_EQ(gt.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(gt[k].t_ns, tiny.frameTime(k));
    EXPECT_LT((gt[k].T_w_c.inverse() * tiny.cameraPoseAt(gt[k].t_ns)).translation().norm(), 1e-4);
  }
  EXPECT_TRUE(fs::exists(dir + "/exposure.txt"));
}

TEST(SynthFastScene, BadFastOptionsAreRefused) {
  for (auto bad : {+[](SceneOptions& o) { o.fast.max_rotation_deg_s = 0; },
                   +[](SceneOptions& o) { o.fast.exposure_ms = 40; },
                   +[](SceneOptions& o) { o.fast.max_subframes = 0; },
                   +[](SceneOptions& o) { o.fast.blur_step_px = 0; }}) {
    SceneOptions o;
    bad(o);
    EXPECT_THROW(makeScene(SceneKind::kFast, o), ConfigError);
  }
  EXPECT_EQ(parseSceneKind("fast"), SceneKind::kFast);
}
