// Intrinsic calibration on synthetic renderings with known intrinsics and distortion.
#include <gtest/gtest.h>

#include <cstdio>
#include <visp3/core/vpXmlParserCamera.h>

#include "calib_fixtures.h"
#include "calibration/intrinsics.h"
#include "calibration/render.h"
#include "camera/camera_file.h"
#include "core/error.h"
#include "support/test_support.h"

using namespace plslam;
using namespace plslam::calib;

namespace {

/// Renders `n` good views (mild blur and noise, as a real camera) and detects them.
std::vector<ViewResult> goodViews(const Target& t, const PinholeCamera& cam, int n, uint32_t seed) {
  TargetDetector det(t);
  std::vector<ViewResult> out;
  const std::vector<SE3> poses = makeViewPoses(t, cam, n, seed);
  for (size_t i = 0; i < poses.size(); ++i) {
    RenderOptions o;
    o.blur_sigma = 0.5;
    o.noise_sigma = 2.0;
    o.seed = seed * 100 + static_cast<uint32_t>(i);
    out.push_back(det.detect(renderTarget(t, cam, poses[i], o), "view" + std::to_string(i)));
  }
  return out;
}

double pct(double est, double truth) { return 100.0 * std::abs(est - truth) / std::abs(truth); }

void expectRecovered(const IntrinsicsResult& r, const PinholeCamera& truth, const char* what) {
  const PinholeCamera& c = r.camera;
  std::printf("%s: %d views used, RMS %.3f px | fx %.2f (%.3f %%) fy %.2f (%.3f %%) cx %.2f (%.3f %%) cy %.2f (%.3f %%) | "
              "k1 %.4f k2 %.4f p1 %.5f p2 %.5f k3 %.4f\n",
              what, r.views_used, r.rms_px, c.fx, pct(c.fx, truth.fx), c.fy, pct(c.fy, truth.fy), c.cx, pct(c.cx, truth.cx),
              c.cy, pct(c.cy, truth.cy), c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4]);
  EXPECT_LT(pct(c.fx, truth.fx), 0.5);
  EXPECT_LT(pct(c.fy, truth.fy), 0.5);
  EXPECT_LT(pct(c.cx, truth.cx), 0.5);
  EXPECT_LT(pct(c.cy, truth.cy), 0.5);
  // Distortion: the displacement it causes is what matters, and is recovered closely even
  // where k2 and k3 trade off. Checked 10 % in from each image corner (the views reach there).
  for (const Eigen::Vector2d& raw : {Eigen::Vector2d(64, 48), Eigen::Vector2d(576, 48), Eigen::Vector2d(64, 432),
                                     Eigen::Vector2d(576, 432)}) {
    const Eigen::Vector2d ideal = truth.undistort(raw);  // ideal pixel of the true camera
    const Eigen::Vector2d xn((ideal.x() - truth.cx) / truth.fx, (ideal.y() - truth.cy) / truth.fy);
    const Eigen::Vector2d est = c.distort({c.fx * xn.x() + c.cx, c.fy * xn.y() + c.cy});
    const double disp_truth = (raw - ideal).norm();
    EXPECT_LT((est - raw).norm(), 1.0) << "at " << raw.transpose() << ": distortion of " << disp_truth << " px";
  }
  EXPECT_NEAR(c.dist[0], truth.dist[0], 0.03);
  EXPECT_NEAR(c.dist[2], truth.dist[2], 0.002);
  EXPECT_NEAR(c.dist[3], truth.dist[3], 0.002);
  EXPECT_LT(r.rms_px, 0.3);
  EXPECT_GT(r.rms_px, 0.0);
}

}  // namespace

TEST(CalibIntrinsics, ChessboardRecoversIntrinsicsWithinHalfAPercent) {
  const PinholeCamera truth = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  const std::vector<ViewResult> views = goodViews(t, truth, 12, 1);
  const IntrinsicsResult r = calibrateIntrinsics(views, {truth.width, truth.height});
  EXPECT_EQ(r.views_used, 12);
  expectRecovered(r, truth, "chessboard 9x6");
}

TEST(CalibIntrinsics, AprilGridRecoversIntrinsicsWithinHalfAPercent) {
  const PinholeCamera truth = test_fixtures::truthCamera();
  const Target t = Target::parse("aprilgrid:6x6:0.04:0.012");
  const std::vector<ViewResult> views = goodViews(t, truth, 12, 2);
  const IntrinsicsResult r = calibrateIntrinsics(views, {truth.width, truth.height});
  EXPECT_GE(r.views_used, 11);
  expectRecovered(r, truth, "aprilgrid 6x6");
}

TEST(CalibIntrinsics, RejectedViewsAreLeftOutWithTheirReasons) {
  const PinholeCamera truth = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  std::vector<ViewResult> views = goodViews(t, truth, 8, 3);
  TargetDetector det(t);
  const SE3 pose = makeViewPoses(t, truth, 1, 4)[0];
  RenderOptions blurred;
  blurred.blur_sigma = 4.0;
  views.push_back(det.detect(renderTarget(t, truth, pose, blurred), "blurred"));
  // Slide the board sideways until it leaves the image, then a third of its width more.
  SE3 cut = pose;
  while (targetInView(t, truth, cut)) cut = SE3(Eigen::Quaterniond::Identity(), {0.01, 0, 0}) * cut;
  cut = SE3(Eigen::Quaterniond::Identity(), {t.patternArea().width / 3, 0, 0}) * cut;
  views.push_back(det.detect(renderTarget(t, truth, cut), "cut"));
  const IntrinsicsResult r = calibrateIntrinsics(views, {truth.width, truth.height});
  EXPECT_EQ(r.views_used, 8);
  EXPECT_EQ(r.views[8].status, ViewStatus::kTooBlurry) << r.views[8].reason;
  EXPECT_EQ(r.views[9].status, ViewStatus::kNotFound) << r.views[9].reason;
  EXPECT_TRUE(std::isnan(r.view_rms_px[8]));
  // Eight views are few: the guidance says so.
  bool says_more_views = false;
  for (const std::string& g : r.guidance) says_more_views |= g.find("10-20") != std::string::npos;
  EXPECT_TRUE(says_more_views);
}

TEST(CalibIntrinsics, MisdetectedViewIsDroppedForHighError) {
  const PinholeCamera truth = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  std::vector<ViewResult> views = goodViews(t, truth, 9, 5);
  // Corrupt one view: a few corners shifted by several pixels (a bent or moving target).
  for (size_t i = 0; i < 10; ++i) views[4].observation.image[i] += cv::Point2f(6.f, -5.f);
  const IntrinsicsResult r = calibrateIntrinsics(views, {truth.width, truth.height});
  EXPECT_EQ(r.views[4].status, ViewStatus::kHighError) << r.views[4].reason;
  EXPECT_EQ(r.views_used, 8);
  EXPECT_LT(pct(r.camera.fx, truth.fx), 0.5);
}

TEST(CalibIntrinsics, TooFewViewsAreRefusedSayingWhy) {
  const PinholeCamera truth = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  std::vector<ViewResult> views = goodViews(t, truth, 3, 6);
  TargetDetector det(t);
  RenderOptions blurred;
  blurred.blur_sigma = 4.0;
  views.push_back(det.detect(renderTarget(t, truth, makeViewPoses(t, truth, 1, 7)[0], blurred), "blurred"));
  try {
    calibrateIntrinsics(views, {truth.width, truth.height});
    FAIL() << "calibrated from 3 views";
  } catch (const DataError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("at least 5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1 too blurry"), std::string::npos) << msg;
  }
}

TEST(CalibIntrinsics, WrittenCameraFileLoadsInViSPAndPlslamWithTheFigures) {
  const PinholeCamera truth = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  IntrinsicsOptions opt;
  opt.model = DistortionModel::kK1K2P1P2;
  opt.camera_name = "my_camera";
  opt.depth_scale = 1000;
  const IntrinsicsResult r = calibrateIntrinsics(goodViews(t, truth, 8, 8), {truth.width, truth.height}, opt);
  EXPECT_EQ(r.camera.dist[4], 0.0);  // k3 held at zero by the model
  const std::string path = test::scratchDir("calibration") + "/my_camera.xml";
  saveCalibration(path, r, t);

  vpXmlParserCamera parser;
  vpCameraParameters vp;
  ASSERT_EQ(parser.parse(vp, path, "my_camera", vpCameraParameters::perspectiveProjWithoutDistortion, 640, 480),
            vpXmlParserCamera::SEQUENCE_OK);
  EXPECT_NEAR(vp.get_px(), r.camera.fx, 1e-6);
  EXPECT_NEAR(vp.get_py(), r.camera.fy, 1e-6);
  EXPECT_NEAR(vp.get_u0(), r.camera.cx, 1e-6);
  EXPECT_NEAR(vp.get_v0(), r.camera.cy, 1e-6);

  const PinholeCamera back = loadCameraFile(path);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(back.dist[i], r.camera.dist[i], 1e-9);
  const std::string text = test::readFile(path);
  EXPECT_NE(text.find("8 of 8 views used"), std::string::npos) << text;
  EXPECT_NE(text.find("reprojection RMS"), std::string::npos) << text;
}

TEST(CalibIntrinsics, DistortionModelsParse) {
  EXPECT_EQ(parseDistortionModel("k1k2"), DistortionModel::kK1K2);
  EXPECT_EQ(parseDistortionModel(distortionModelName(DistortionModel::kNone)), DistortionModel::kNone);
  EXPECT_THROW(parseDistortionModel("k4"), ConfigError);
}
