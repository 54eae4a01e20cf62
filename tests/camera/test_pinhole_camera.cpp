#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <visp3/core/vpMeterPixelConversion.h>

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

// Every pixel of a grid unprojected at 2.5 m and projected again lands where it started.
void expectProjectUnprojectRoundTrip(const PinholeCamera& cam) {
  for (double u = 20; u < 640; u += 77)
    for (double v = 15; v < 480; v += 61) {
      const Eigen::Vector3d p = cam.unproject({u, v}, 2.5);
      EXPECT_NEAR(p.z(), 2.5, 1e-12);
      const Eigen::Vector2d uv = cam.project(p);
      EXPECT_NEAR(uv.x(), u, 1e-6);
      EXPECT_NEAR(uv.y(), v, 1e-6);
    }
}
}  // namespace

TEST(PinholeCamera, ProjectUnprojectRoundTripWithDistortion) {
  expectProjectUnprojectRoundTrip(freiburg1());
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
  for (double bad : {0.0, -0.0, 1e-9, -1e-9, std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    for (double* f : {&cam.fx, &cam.fy}) {
      cam = freiburg1();
      *f = bad;
      try {
        cam.validate("my.xml");
        ADD_FAILURE() << "focal length " << bad << " accepted";
      } catch (const DataError& e) {
        EXPECT_NE(std::string(e.what()).find("my.xml"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("focal"), std::string::npos) << e.what();
      }
    }
  }
  cam = freiburg1();
  cam.cx = 900;
  EXPECT_THROW(cam.validate("x"), DataError);
  cam = freiburg1();
  cam.depth_scale = 0;
  EXPECT_THROW(cam.validate("x"), DataError);
}

namespace {
// The camera that sees the images of `cam` flipped: rows (flip_rows) and/or columns.
PinholeCamera mirrored(PinholeCamera cam, bool flip_rows, bool flip_cols) {
  if (flip_rows) cam.fy = -cam.fy, cam.cy = (cam.height - 1) - cam.cy;
  if (flip_cols) cam.fx = -cam.fx, cam.cx = (cam.width - 1) - cam.cx;
  return cam;
}
}  // namespace

TEST(PinholeCamera, NegativeFocalLengthsAreValidAndRoundTrip) {
  // ICL-NUIM's published intrinsics, and both axes flipped, with and without distortion.
  PinholeCamera icl;
  icl.width = 640, icl.height = 480;
  icl.fx = 481.2, icl.fy = -480.0, icl.cx = 319.5, icl.cy = 239.5;
  PinholeCamera both = freiburg1();
  both.fx = -both.fx, both.fy = -both.fy;
  for (const PinholeCamera& cam : {icl, mirrored(freiburg1(), true, false), both}) {
    SCOPED_TRACE(testing::Message() << "fx " << cam.fx << " fy " << cam.fy);
    EXPECT_NO_THROW(cam.validate("negative.xml"));
    expectProjectUnprojectRoundTrip(cam);
    for (double u = 20; u < 640; u += 77)
      for (double v = 15; v < 480; v += 61) {
        const Eigen::Vector3d p = cam.unproject({u, v}, 2.5);
        const Eigen::Vector2d ideal = cam.undistort({u, v});
        EXPECT_LT((cam.distort(ideal) - Eigen::Vector2d(u, v)).norm(), 1e-6);
        EXPECT_LT((cam.unprojectIdeal(ideal, 2.5) - p).norm(), 1e-9);
        EXPECT_LT((cam.projectIdeal(p) - ideal).norm(), 1e-9);
      }
  }
  // fy < 0: a point above the optical axis (y < 0) lands below the principal point.
  EXPECT_GT(icl.projectIdeal({0.0, -0.5, 2.0}).y(), icl.cy);
  EXPECT_EQ(icl.imageUp(), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(freiburg1().imageUp(), Eigen::Vector3d(0, -1, 0));
}

TEST(PinholeCamera, MirroredCameraSeesTheFlippedImage) {
  // The camera of flipped images (fy -> -fy, cy -> h-1-cy; likewise for columns) puts every
  // camera-frame point on the flipped pixel, through the distortion too, and unprojects the
  // flipped pixel (depth looked up in the flipped depth image) to the same point.
  const PinholeCamera cam = freiburg1();
  cv::Mat depth(cam.height, cam.width, CV_32FC1);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) depth.at<float>(y, x) = 1.0f + 0.001f * x + 0.002f * y;
  for (bool rows : {true, false})
    for (bool cols : {true, false}) {
      if (!rows && !cols) continue;
      SCOPED_TRACE(testing::Message() << "rows " << rows << " cols " << cols);
      const PinholeCamera m = mirrored(cam, rows, cols);
      cv::Mat flipped;
      cv::flip(depth, flipped, rows && cols ? -1 : rows ? 0 : 1);
      auto flip = [&](const Eigen::Vector2d& uv) {
        return Eigen::Vector2d(cols ? cam.width - 1 - uv.x() : uv.x(), rows ? cam.height - 1 - uv.y() : uv.y());
      };
      for (double u = 20; u < 640; u += 53)
        for (double v = 15; v < 480; v += 41) {
          const Eigen::Vector2d uv(u, v);
          const Eigen::Vector3d p = cam.unproject(uv, depthAt(depth, u, v));
          EXPECT_LT((m.project(p) - flip(uv)).norm(), 1e-6);
          EXPECT_LT((m.undistort(flip(uv)) - flip(cam.undistort(uv))).norm(), 1e-6);
          EXPECT_EQ(depthAt(flipped, flip(uv).x(), flip(uv).y()), depthAt(depth, u, v));
          const Eigen::Vector2d fuv = flip(uv);
          EXPECT_LT((m.unproject(fuv, depthAt(flipped, fuv.x(), fuv.y())) - p).norm(), 1e-9);
          EXPECT_EQ(m.inImage(fuv, 5.0), cam.inImage(uv, 5.0));
        }
      EXPECT_FALSE(m.inImage({-0.5, 10}));
      EXPECT_FALSE(m.inImage({10, cam.height - 0.5}));
    }
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

TEST(VispConversion, NegativeFocalLengthKeepsItsSign) {
  // ViSP accepts a negative px or py and projects with it as plslam does.
  PinholeCamera cam = freiburg1();
  cam.dist = {};
  cam.fy = -cam.fy;
  cam.cy = 479 - cam.cy;
  const vpCameraParameters vp = toVisp(cam);
  EXPECT_DOUBLE_EQ(vp.get_py(), cam.fy);
  const Eigen::Vector3d p(0.3, -0.4, 2.0);
  double u = 0, v = 0;
  vpMeterPixelConversion::convertPoint(vp, p.x() / p.z(), p.y() / p.z(), u, v);
  EXPECT_NEAR(u, cam.project(p).x(), 1e-9);
  EXPECT_NEAR(v, cam.project(p).y(), 1e-9);
  const PinholeCamera back = fromVisp(vp, 640, 480, 5000);
  EXPECT_DOUBLE_EQ(back.fy, cam.fy);
  EXPECT_NO_THROW(back.validate("visp"));
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
