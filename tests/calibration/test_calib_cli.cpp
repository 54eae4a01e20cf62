// `plslam calib`: render synthetic views, then calibrate them end to end through the CLI.
#include <gtest/gtest.h>

#include <filesystem>

#include "calibration/base_transform.h"
#include "camera/camera_file.h"
#include "support/test_support.h"

using namespace plslam;
namespace fs = std::filesystem;

TEST(CalibCli, RenderThenIntrinsicsRecoversTheCameraAndRejectsTheBadViews) {
  const std::string dir = test::scratchDir("calib_cli");
  auto r = test::runPlslam("calib render --out " + dir + " --target chessboard:9x6:0.03 --views 10 --bad-views");
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::runPlslam("calib intrinsics --images " + dir + "/colour --target chessboard:9x6:0.03 --out " + dir +
                      "/cam.xml --truth " + dir + "/truth_camera.xml");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("bad_blurred.png: REJECTED: too blurry"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bad_cut.png: REJECTED: chessboard 9x6 not found"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("10 of 12 views used"), std::string::npos) << r.output;
  const PinholeCamera cam = loadCameraFile(dir + "/cam.xml"), truth = loadCameraFile(dir + "/truth_camera.xml");
  EXPECT_NEAR(cam.fx, truth.fx, 0.005 * truth.fx);
  EXPECT_NEAR(cam.cy, truth.cy, 0.005 * truth.cy);
}

TEST(CalibCli, DepthFindsTheSimulatedScaleAndOffset) {
  const std::string dir = test::scratchDir("calib_cli_depth");
  auto r = test::runPlslam("calib render --out " + dir +
                           " --target chessboard:9x6:0.03 --views 5 --depth --depth-scale-error 1.02 --depth-offset 0.01");
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::runPlslam("calib depth --colour " + dir + "/colour --depth " + dir + "/depth --camera " + dir +
                      "/truth_camera.xml --target chessboard:9x6:0.03");
  ASSERT_EQ(r.status, 0) << r.output;
  const size_t at = r.output.find("measured = ");
  ASSERT_NE(at, std::string::npos) << r.output;
  double scale = 0, offset = 0;
  ASSERT_EQ(std::sscanf(r.output.c_str() + at, "measured = %lf * true %lf", &scale, &offset), 2) << r.output;
  EXPECT_NEAR(scale, 1.02, 0.005) << r.output;
  EXPECT_NEAR(offset, 0.01, 0.003) << r.output;
}

TEST(CalibCli, BaseWritesATransformNearTheTruth) {
  const std::string dir = test::scratchDir("calib_cli_base");
  auto r = test::runPlslam("calib render --out " + dir +
                           " --target tag:0:0.12 --views 4 --camera-to-base 0.09,0.01,0.18,-102,0,-90 "
                           "--tag-pose 0.45,0.02,0.15,-90,0,-80");
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::runPlslam("calib base --images " + dir + "/colour --camera " + dir +
                      "/truth_camera.xml --target tag:0:0.12 --tag-pose 0.45,0.02,0.15,-90,0,-80 --out " + dir +
                      "/base.yaml --truth " + dir + "/truth_camera_to_base.yaml");
  ASSERT_EQ(r.status, 0) << r.output;
  const SE3 est = calib::loadCameraToBase(dir + "/base.yaml"), truth = calib::loadCameraToBase(dir + "/truth_camera_to_base.yaml");
  EXPECT_LT((est.translation() - truth.translation()).norm(), 0.005) << r.output;
  EXPECT_LT((truth.inverse() * est).angle(), 0.5 * M_PI / 180) << r.output;
}

TEST(CalibCli, BadArgumentsAreRefused) {
  auto r = test::runPlslam("calib nope");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("unknown subcommand 'nope'"), std::string::npos) << r.output;
  r = test::runPlslam("calib intrinsics --images /tmp --out /tmp/x.xml");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--target"), std::string::npos) << r.output;
  r = test::runPlslam("calib intrinsics --images /nonexistent --target chessboard:9x6:0.03 --out /tmp/x.xml");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("/nonexistent"), std::string::npos) << r.output;
}
