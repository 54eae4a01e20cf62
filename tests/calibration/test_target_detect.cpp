// Targets, the renderer and the detectors: specs parse, rendered corners are where the
// camera model puts them, and rejected views carry the right reason.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib_fixtures.h"
#include "calibration/detect.h"
#include "calibration/render.h"
#include "calibration/target.h"
#include "core/error.h"

using namespace plslam;
using namespace plslam::calib;

namespace {

/// A view of the whole target straight ahead, slightly tilted, filling about `fill` of the width.
SE3 frontView(const Target& t, const PinholeCamera& cam, double fill, double tilt_deg = 10.0) {
  const double distance = cam.fx * t.patternArea().width / (fill * cam.width);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(tilt_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return SE3(R, Eigen::Vector3d(0, 0, distance)) * t.boardFromTarget().inverse();
}

/// Largest and RMS distance between detected points and the true projection of their board points.
std::pair<double, double> cornerErrors(const Observation& obs, const PinholeCamera& cam, const SE3& T_c_b) {
  double worst = 0, sq = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    const cv::Point3f& o = obs.object[i];
    const Eigen::Vector2d uv = cam.project(T_c_b * Eigen::Vector3d(o.x, o.y, o.z));
    const double e = std::hypot(uv.x() - obs.image[i].x, uv.y() - obs.image[i].y);
    worst = std::max(worst, e);
    sq += e * e;
  }
  return {worst, std::sqrt(sq / std::max<size_t>(1, obs.size()))};
}

}  // namespace

TEST(CalibTarget, SpecsParseAndRoundTrip) {
  for (const char* spec : {"chessboard:9x6:0.025", "aprilgrid:6x6:0.04:0.012", "aprilgrid:4x3:0.05:0.01:20", "tag:7:0.16"}) {
    const Target t = Target::parse(spec);
    EXPECT_EQ(t.spec(), spec);
    EXPECT_EQ(Target::parse(t.spec()), t);
  }
  const Target cb = Target::parse("chessboard:9x6:0.025");
  EXPECT_EQ(cb.pointCount(), 54);
  EXPECT_FLOAT_EQ(cb.points()[10].x, 0.025f);  // second row, second corner
  EXPECT_FLOAT_EQ(cb.points()[10].y, 0.025f);
  const Target g = Target::parse("aprilgrid:6x6:0.04:0.012:3");
  EXPECT_EQ(g.pointCount(), 144);
  EXPECT_EQ(g.tagPointId(3, 0), 0);
  EXPECT_EQ(g.tagPointId(2, 0), -1);
  EXPECT_EQ(g.tagPointId(3 + 36, 0), -1);
  const Target tag = Target::parse("tag:5:0.1");
  EXPECT_NEAR(tag.boardFromTarget().translation().x(), 0.05, 1e-12);
}

TEST(CalibTarget, BadSpecsAreRefusedNamingTheProblem) {
  const std::pair<const char*, const char*> bad[] = {
      {"chessboard:9:0.025", "COLSxROWS"}, {"chessboard:9x6", "expected"}, {"chessboard:9x6:-1", "size"},
      {"aprilgrid:6x6:0.04", "expected"}, {"aprilgrid:30x30:0.04:0.01", "587"}, {"circles:4x4:0.1", "unknown kind"},
      {"chessboard:9x6:abc", "not a number"}};
  for (const auto& [spec, needle] : bad) {
    try {
      Target::parse(spec);
      ADD_FAILURE() << "accepted " << spec;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(spec), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
  }
}

TEST(CalibDetect, ChessboardCornersAreWhereTheCameraModelPutsThem) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  const SE3 T = frontView(t, cam, 0.6, 20.0);
  const cv::Mat img = renderTarget(t, cam, T);
  TargetDetector det(t);
  const ViewResult r = det.detect(img, "front");
  ASSERT_EQ(r.status, ViewStatus::kAccepted) << r.reason;
  ASSERT_EQ(r.observation.size(), 54u);
  const auto [worst, rms] = cornerErrors(r.observation, cam, T);
  EXPECT_LT(worst, 0.3);
  EXPECT_LT(rms, 0.12);
}

TEST(CalibDetect, AprilGridCornersAreWhereTheCameraModelPutsThemInTheLibraryOrder) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("aprilgrid:6x6:0.04:0.012:10");
  const SE3 T = frontView(t, cam, 0.6, 20.0);
  ASSERT_TRUE(targetInView(t, cam, T, 2));
  const cv::Mat img = renderTarget(t, cam, T);
  TargetDetector det(t);
  const ViewResult r = det.detect(img, "front");
  ASSERT_EQ(r.status, ViewStatus::kAccepted) << r.reason;
  EXPECT_EQ(r.tags, 36);
  // A wrong corner order or pixel convention would be off by pixels.
  const auto [worst, rms] = cornerErrors(r.observation, cam, T);
  EXPECT_LT(worst, 0.5);
  EXPECT_LT(rms, 0.25);
}

TEST(CalibDetect, BlurredViewIsRejectedAsTooBlurry) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  for (const char* spec : {"chessboard:9x6:0.03", "aprilgrid:6x6:0.04:0.012"}) {
    const Target t = Target::parse(spec);
    const SE3 T = frontView(t, cam, 0.6);
    TargetDetector det(t);
    RenderOptions sharp;
    sharp.noise_sigma = 2.0;
    sharp.blur_sigma = 0.6;
    const ViewResult ok = det.detect(renderTarget(t, cam, T, sharp), "sharp");
    EXPECT_EQ(ok.status, ViewStatus::kAccepted) << spec << ": " << ok.reason;
    RenderOptions blurred = sharp;
    blurred.blur_sigma = 3.5;
    const ViewResult r = det.detect(renderTarget(t, cam, T, blurred), "blurred");
    EXPECT_EQ(r.status, ViewStatus::kTooBlurry) << spec << ": " << r.reason << " (sharpness " << r.sharpness
                                                << ", sharp view " << ok.sharpness << ")";
    EXPECT_NE(r.reason.find("blurry"), std::string::npos) << r.reason;
  }
}

TEST(CalibDetect, TargetPartlyOutOfViewIsRejectedWithTheReason) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  {
    const Target t = Target::parse("chessboard:9x6:0.03");
    const SE3 T = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.17, 0, 0)) * frontView(t, cam, 0.6);
    ASSERT_FALSE(targetInView(t, cam, T));
    TargetDetector det(t);
    const ViewResult r = det.detect(renderTarget(t, cam, T), "cut");
    EXPECT_EQ(r.status, ViewStatus::kNotFound) << r.reason;
    EXPECT_NE(r.reason.find("whole board"), std::string::npos) << r.reason;
  }
  {
    // Only about one tag in the image's bottom-right corner stays in view: too few tags.
    const Target t = Target::parse("aprilgrid:6x6:0.04:0.012");
    const SE3 base = frontView(t, cam, 0.8, 0.0);
    const double z = base.translation().z(), w = t.patternArea().width, pitch = t.size + t.spacing;
    // Shift so that the pattern's top-left sits 1.4 tag pitches inside the bottom-right image corner.
    const double sx = (cam.width - cam.cx) * z / cam.fx - 1.4 * pitch + 0.5 * w;
    const double sy = (cam.height - cam.cy) * z / cam.fy - 1.4 * pitch + 0.5 * w;
    const SE3 T = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(sx, sy, 0)) * base;
    TargetDetector det(t);
    const ViewResult r = det.detect(renderTarget(t, cam, T), "cut");
    EXPECT_EQ(r.status, ViewStatus::kTooFewPoints) << r.reason << " (" << r.tags << " tags)";
    EXPECT_GT(r.tags, 0);
    EXPECT_NE(r.reason.find("tags found"), std::string::npos) << r.reason;
  }
}

TEST(CalibDetect, DistantTargetIsRejectedForPoorCoverage) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("aprilgrid:3x3:0.04:0.012");
  const SE3 T = frontView(t, cam, 0.16, 0.0);
  TargetDetector det(t);
  const ViewResult r = det.detect(renderTarget(t, cam, T), "far");
  EXPECT_EQ(r.status, ViewStatus::kPoorCoverage) << r.reason;
  EXPECT_NE(r.reason.find("move closer"), std::string::npos) << r.reason;
}

TEST(CalibDetect, ImageWithoutTargetIsNotFound) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  // The board behind the camera: a plain background image with noise.
  RenderOptions o;
  o.noise_sigma = 2;
  const cv::Mat img = renderTarget(Target::parse("aprilgrid:2x2:0.04:0.01"), cam, frontView(t, cam, 0.5), o);
  TargetDetector det(t);
  const ViewResult r = det.detect(img, "empty");
  EXPECT_TRUE(r.status == ViewStatus::kNotFound) << viewStatusName(r.status) << ": " << r.reason;
}

TEST(CalibRender, ViewPosesKeepTheTargetInViewAndAreDeterministic) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("aprilgrid:6x6:0.04:0.012");
  const auto a = makeViewPoses(t, cam, 8, 3), b = makeViewPoses(t, cam, 8, 3);
  ASSERT_EQ(a.size(), 8u);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(targetInView(t, cam, a[i], 5));
    EXPECT_EQ(a[i].translation(), b[i].translation());
  }
}
