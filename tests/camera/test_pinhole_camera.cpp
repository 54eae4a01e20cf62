#include <gtest/gtest.h>

#include <cmath>

#include "camera/pinhole_camera.h"
#include "camera/visp_conversion.h"
#include "core/error.h"

using namespace plslam;

namespace {
PinholeCamera freiburg1() {
  PinholeCamera c;
  c.name = "fr1";
  c.width = 640;
  c.height = 480;
  c.fx = 517.3;
  c.fy = 516.5;
  c.cx = 318.6;
  c.cy = 255.3;
  c.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  return c;
}
}  // namespace

TEST(PinholeCamera, ProjectUnprojectRoundTripWithDistortion) {
  const PinholeCamera cam = freiburg1();
  for (double u = 20; u < 640; u += 77)
    for (double v = 15; v < 480; v += 61) {
      const Eigen::Vector3d p = cam.unproject({u, v}, 2.5);
      EXPECT_NEAR(p.z(), 2.5, 1e-12);
      const Eigen::Vector2d uv = cam.project(p);
      EXPECT_NEAR(uv.x(), u, 1e-6);
      EXPECT_NEAR(uv.y(), v, 1e-6);
    }
}

TEST(PinholeCamera, DistortionMovesCornersButNotCentre) {
  const PinholeCamera cam = freiburg1();
  const Eigen::Vector2d c(cam.cx, cam.cy);
  EXPECT_LT((cam.distort(c) - c).norm(), 1e-12);
  const Eigen::Vector2d corner(10, 10);
  EXPECT_GT((cam.undistort(corner) - corner).norm(), 1.0);
}

TEST(PinholeCamera, ValidateRefusesBadIntrinsicsNamingSource) {
  PinholeCamera cam = freiburg1();
  cam.fy = -480;
  try {
    cam.validate("my.xml");
    FAIL() << "negative focal length accepted";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("my.xml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("focal"), std::string::npos);
  }
  cam = freiburg1();
  cam.fx = std::nan("");
  EXPECT_THROW(cam.validate("x"), DataError);
  cam = freiburg1();
  cam.cx = 900;
  EXPECT_THROW(cam.validate("x"), DataError);
  cam = freiburg1();
  cam.depth_scale = 0;
  EXPECT_THROW(cam.validate("x"), DataError);
}

TEST(PinholeCamera, DepthConversionRoundTripAndHoles) {
  cv::Mat raw(2, 3, CV_16UC1);
  raw.at<uint16_t>(0, 0) = 0;
  raw.at<uint16_t>(0, 1) = 5000;
  raw.at<uint16_t>(0, 2) = 12345;
  raw.at<uint16_t>(1, 0) = 1;
  raw.at<uint16_t>(1, 1) = 65535;
  raw.at<uint16_t>(1, 2) = 2500;
  const cv::Mat m = depthToMetres(raw, 5000.0);
  EXPECT_TRUE(std::isnan(m.at<float>(0, 0)));
  EXPECT_FLOAT_EQ(m.at<float>(0, 1), 1.0f);
  EXPECT_TRUE(std::isnan(depthAt(m, 0, 0)));
  EXPECT_TRUE(std::isnan(depthAt(m, -3, 0)));
  EXPECT_FLOAT_EQ(depthAt(m, 2.2, 1.1), 0.5f);
  const cv::Mat back = metresToDepth(m, 5000.0);
  EXPECT_EQ(cv::countNonZero(back != raw), 0);
}

TEST(VispConversion, CameraParametersRoundTrip) {
  PinholeCamera cam = freiburg1();
  cam.dist = {};
  const vpCameraParameters vp = toVisp(cam);
  EXPECT_DOUBLE_EQ(vp.get_px(), cam.fx);
  EXPECT_DOUBLE_EQ(vp.get_v0(), cam.cy);
  const PinholeCamera back = fromVisp(vp, 640, 480, 5000);
  EXPECT_DOUBLE_EQ(back.fy, cam.fy);
  EXPECT_DOUBLE_EQ(back.cx, cam.cx);
  EXPECT_FALSE(back.hasDistortion());
  // A ViSP model with distortion: kud is Brown's k1, and both models distort alike.
  const vpCameraParameters vpd(500, 500, 320, 240, 0.1, -0.1);
  const PinholeCamera withk1 = fromVisp(vpd, 640, 480, 1000);
  EXPECT_DOUBLE_EQ(withk1.dist[0], 0.1);
  const double x = 0.3, y = -0.2;  // normalised ideal coordinates
  const Eigen::Vector2d uv = withk1.distort({320 + 500 * x, 240 + 500 * y});
  const double r2 = x * x + y * y;
  EXPECT_NEAR(uv.x(), 320 + 500 * x * (1 + 0.1 * r2), 1e-9);
}

TEST(VispConversion, PoseIsAMbWithoutInversion) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.5, -1, 2, 0.3, 0.1, -0.2;
  const SE3 T_a_b = SE3::exp(xi);
  const vpHomogeneousMatrix aMb = toVisp(T_a_b);
  const vpColVector p_b({0.1, 0.2, 0.3, 1.0});
  const vpColVector p_a = aMb * p_b;
  const Eigen::Vector3d e = T_a_b * Eigen::Vector3d(0.1, 0.2, 0.3);
  EXPECT_NEAR(p_a[0], e.x(), 1e-12);
  EXPECT_NEAR(p_a[2], e.z(), 1e-12);
  EXPECT_LT((fromVisp(aMb).matrix() - T_a_b.matrix()).norm(), 1e-12);
}
