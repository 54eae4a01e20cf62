// Depth scale/offset against a plane and the camera-to-base transform, on renderings.
#include <gtest/gtest.h>

#include <cstdio>

#include "calib_fixtures.h"
#include "calibration/base_transform.h"
#include "calibration/depth_check.h"
#include "calibration/detect.h"
#include "calibration/intrinsics.h"
#include "calibration/render.h"
#include "core/error.h"
#include "support/test_support.h"

using namespace plslam;
using namespace plslam::calib;

TEST(CalibDepth, ScaleAndOffsetAreRecoveredFromBoardViews) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("aprilgrid:6x6:0.04:0.012");
  ViewPoseOptions po;
  po.min_fill = 0.35;  // a spread of distances separates scale from offset
  po.max_fill = 0.9;
  const std::vector<SE3> poses = makeViewPoses(t, cam, 6, 11, po);
  const double scale = 1.025, offset = -0.012;
  TargetDetector det(t);
  std::vector<DepthView> views;
  for (size_t i = 0; i < poses.size(); ++i) {
    RenderOptions ro;
    ro.noise_sigma = 2;
    ro.blur_sigma = 0.5;
    ro.seed = static_cast<uint32_t>(i + 1);
    const ViewResult r = det.detect(renderTarget(t, cam, poses[i], ro), "v" + std::to_string(i));
    ASSERT_TRUE(r.accepted()) << r.reason;
    DepthRenderOptions dro;
    dro.scale = scale;
    dro.offset = offset;
    dro.noise_sigma = 0.003;
    dro.seed = static_cast<uint32_t>(i + 1);
    // The board pose comes from the colour image, as the tool does it.
    views.push_back({r.name, renderPlaneDepth(cam, poses[i], dro), estimateBoardPose(r.observation, cam)});
  }
  // A few wild depth readings (flying pixels) must not move the fit.
  views[0].depth_m(cv::Rect(300, 220, 20, 20)).setTo(5.0f);
  const DepthFit fit = fitDepthScaleOffset(views, cam, t);
  std::printf("depth: scale %.5f (truth %.5f) offset %+.5f m (truth %+.5f) RMS %.4f m over %d pixels, %d views, "
              "true depth %.2f-%.2f m\n",
              fit.scale, scale, fit.offset, offset, fit.rms_m, fit.pixels, fit.views, fit.min_true_m, fit.max_true_m);
  EXPECT_NEAR(fit.scale, scale, 0.003);
  EXPECT_NEAR(fit.offset, offset, 0.002);
  EXPECT_NEAR(fit.rms_m, 0.003, 0.001);  // the simulated noise
  EXPECT_EQ(fit.views, 6);
}

TEST(CalibDepth, ViewsWithoutDepthAreSkippedAndNoDepthAtAllIsRefused) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target t = Target::parse("chessboard:9x6:0.03");
  const SE3 pose = makeViewPoses(t, cam, 1, 12)[0];
  std::vector<DepthView> views{{"empty", cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(0)), pose}};
  EXPECT_THROW(fitDepthScaleOffset(views, cam, t), DataError);
  views.push_back({"good", renderPlaneDepth(cam, pose), pose});
  const DepthFit fit = fitDepthScaleOffset(views, cam, t);
  EXPECT_EQ(fit.views, 1);
  ASSERT_FALSE(fit.view_notes.empty());
  EXPECT_NE(fit.view_notes[0].find("empty: skipped"), std::string::npos) << fit.view_notes[0];
  EXPECT_FALSE(fit.guidance.empty());  // one distance only: add views
}

TEST(CalibBase, CameraToBaseIsRecoveredFromTagViews) {
  const PinholeCamera cam = test_fixtures::truthCamera();
  const Target tag = Target::parse("tag:3:0.12");
  // TurtleBot3-like: camera 9 cm ahead of the base origin, 18 cm up, looking ahead and 12
  // degrees down; the tag upright on a jig 45 cm ahead, 15 cm up, turned 10 degrees.
  const double d = M_PI / 180;
  const SE3 T_b_c(rotationFromRpy(-90 * d - 12 * d, 0, -90 * d), Eigen::Vector3d(0.09, 0.01, 0.18));
  const SE3 T_b_tag = parsePoseXyzRpyDeg("0.45,0.02,0.15,-90,0,-80", "--tag-pose");
  const SE3 T_c_board = T_b_c.inverse() * T_b_tag * tag.boardFromTarget().inverse();
  ASSERT_TRUE(targetInView(tag, cam, T_c_board, 5));
  TargetDetector det(tag);
  std::vector<SE3> T_c_tag;
  for (uint32_t i = 0; i < 6; ++i) {
    RenderOptions ro;
    ro.noise_sigma = 2;
    ro.blur_sigma = 0.6;
    ro.seed = i + 1;
    const ViewResult r = det.detect(renderTarget(tag, cam, T_c_board, ro), "v");
    ASSERT_TRUE(r.accepted()) << r.reason;
    T_c_tag.push_back(estimateBoardPose(r.observation, cam) * tag.boardFromTarget());
  }
  const CameraToBase c = cameraToBase(T_c_tag, T_b_tag);
  const SE3 err = T_b_c.inverse() * c.T_b_c;
  std::printf("camera-to-base: translation error %.2f mm, rotation error %.3f deg, spread %.2f mm / %.3f deg over %d views\n",
              1000 * (c.T_b_c.translation() - T_b_c.translation()).norm(), err.angle() / d, 1000 * c.spread_t_m,
              c.spread_r_deg, c.views);
  EXPECT_LT((c.T_b_c.translation() - T_b_c.translation()).norm(), 0.003);
  EXPECT_LT(err.angle(), 0.3 * d);
  EXPECT_EQ(c.views, 6);

  const std::string path = test::scratchDir("calibration") + "/camera_to_base.yaml";
  saveCameraToBase(path, c, "test");
  const SE3 back = loadCameraToBase(path);
  EXPECT_LT((back.translation() - c.T_b_c.translation()).norm(), 1e-9);
  EXPECT_LT((back.inverse() * c.T_b_c).angle(), 1e-9);
}

TEST(CalibBase, RpyAndAveragingAreConsistent) {
  const Eigen::Vector3d rpy(0.3, -0.4, 2.0);
  EXPECT_LT((rpyFromRotation(rotationFromRpy(rpy.x(), rpy.y(), rpy.z())) - rpy).norm(), 1e-12);
  // The optical frame of a forward-looking camera: rpy (-90, 0, -90) degrees.
  const Eigen::Matrix3d R = rotationFromRpy(-M_PI / 2, 0, -M_PI / 2);
  EXPECT_LT((R.col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-12);  // z forward = base x
  EXPECT_LT((R.col(0) + Eigen::Vector3d::UnitY()).norm(), 1e-12);  // x right = -base y
  const SE3 a(rotationFromRpy(0.1, 0, 0), Eigen::Vector3d(1, 0, 0)), b(rotationFromRpy(-0.1, 0, 0), Eigen::Vector3d(3, 0, 0));
  const SE3 m = averagePoses({a, b});
  EXPECT_LT(m.angle(), 1e-12);
  EXPECT_NEAR(m.translation().x(), 2.0, 1e-12);
}

TEST(CalibBase, BadPoseTextAndFilesAreRefusedNamingThem) {
  EXPECT_THROW(parsePoseXyzRpyDeg("1,2,3", "--tag-pose"), ConfigError);
  EXPECT_THROW(parsePoseXyzRpyDeg("1,2,3,a,0,0", "--tag-pose"), ConfigError);
  const std::string dir = test::scratchDir("calibration_base");
  const std::string bad = dir + "/bad.yaml";
  const auto refused = [&](const char* content, const std::string& needle) {
    FILE* f = std::fopen(bad.c_str(), "w");
    std::fputs(content, f);
    std::fclose(f);
    try {
      loadCameraToBase(bad);
      ADD_FAILURE() << "accepted:\n" << content;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  refused("format: plslam_camera_to_base 1\ntranslation: [0, 0, 0]\nrotation: [0, 0, 0, 2]\n", "bad.yaml:3: rotation quaternion has norm 2");
  refused("# c\nformat: plslam_camera_to_base 1\ntranslation: [0, 0]\nrotation: [0, 0, 0, 1]\n",
          "bad.yaml:3: translation must be a list of 3 numbers");
  refused("format: plslam_camera_to_base 1\ntranslation: [0, 0, 0]\nrotation: [0, 0, x, 1]\n", "bad.yaml:3: rotation: 'x' is not a number");
  refused("format: plslam_camera_to_base 1\ntranslation: [0, 0, 0]\n", "bad.yaml:1: no 'rotation' key");
  refused("translation: [0, 0, 0]\nrotation: [0, 0, 0, 1]\n", "not a camera-to-base file");
  refused("format: plslam_camera_to_base 1\ntranslation: [0, 0, 0\n", "bad.yaml:");
  EXPECT_THROW(loadCameraToBase(dir + "/missing.yaml"), IoError);
}
