// The transport-neutral session under the ROS node: configuration from switches, frames
// pushed from another thread, outputs; and the robot frame conventions (REP-103/105).
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "camera/camera_file.h"
#include "core/error.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "session/live_session.h"
#include "session/robot_frames.h"
#include "support/test_support.h"
#include "synthetic_cache.h"

using namespace plslam;

TEST(RobotFrames, OpticalAxesBecomeForwardLeftUp) {
  const RobotFrames frames;  // no calibration: the level camera at the base origin
  const SE3 T_base_cam = frames.T_base_cam();
  EXPECT_TRUE((T_base_cam * Eigen::Vector3d(0, 0, 1)).isApprox(Eigen::Vector3d(1, 0, 0)));   // forward
  EXPECT_TRUE((T_base_cam * Eigen::Vector3d(-1, 0, 0)).isApprox(Eigen::Vector3d(0, 1, 0)));  // left
  EXPECT_TRUE((T_base_cam * Eigen::Vector3d(0, -1, 0)).isApprox(Eigen::Vector3d(0, 0, 1)));  // up
  // At the first frame the base is at map's origin, whatever T_base_cam is.
  const SE3 mounted(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(0.09, 0.01, 0.18));
  const RobotFrames robot(mounted);
  EXPECT_TRUE(robot.T_map_base(SE3()).translation().isZero(1e-12));
  // The camera moving 1 m along its optical axis moves the base 1 m forward in map.
  const SE3 T_w_c(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 1));
  EXPECT_TRUE(robot.T_map_base(T_w_c).translation().isApprox(mounted * Eigen::Vector3d(0, 0, 1) - mounted.translation()));
  EXPECT_TRUE(robot.T_map_cam(T_w_c).translation().isApprox(mounted * Eigen::Vector3d(0, 0, 1)));
}

TEST(RunConfig, SwitchesOverTheFileAndRefusedCombinations) {
  RunSwitches s;
  s.no_lines = true;
  s.no_loop = true;
  s.dynamic_classes = "person,dog";
  const RunConfig c = makeRunConfig(s, "test");
  EXPECT_FALSE(c.options.use_lines);
  EXPECT_FALSE(c.options.use_loop);
  ASSERT_TRUE(c.options.segmenter.dynamic_classes.has_value());
  EXPECT_EQ(c.options.segmenter.dynamic_classes->size(), 2u);
  EXPECT_NE(c.config_yaml.find("use_lines: false"), std::string::npos) << c.config_yaml;
  s.localize = true;
  EXPECT_THROW(makeRunConfig(s, "test"), ConfigError);
}

TEST(LiveSession, PushedFramesWithoutDropsTrackLikeTheSystem) {
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 40);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  RunSwitches s;
  s.sequential = true;
  SessionOptions so;
  so.drop_frames = false;
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<FrameOutcome> outcomes;
  session.setFrameListener([&](const FrameOutcome& f) { outcomes.push_back(f); });
  session.start();
  TumDataset dataset = TumDataset::open(folder, camera);
  std::thread producer([&] {
    RgbdFrame frame;
    while (dataset.next(&frame)) session.push(deepCopy(frame));
  });
  producer.join();
  session.stop();
  const SessionCounts c = session.counts();
  EXPECT_EQ(c.received, 40);
  EXPECT_EQ(c.processed, 40);
  EXPECT_EQ(c.dropped, 0);
  ASSERT_EQ(outcomes.size(), 40u);
  EXPECT_GT(session.sparseMap().points.size(), 100u);

  // The same frames straight into a System give the same trajectory.
  SystemOptions options = makeRunConfig(s, "test").options;
  System direct(camera, options);
  direct.start();
  dataset.rewind();
  RgbdFrame frame;
  while (dataset.next(&frame)) direct.feed(frame);
  direct.finish();
  const Trajectory a = session.system().trajectory(), b = direct.trajectory();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].T_w_c.translation().isApprox(b[i].T_w_c.translation(), 1e-12)) << i;
  EXPECT_TRUE(outcomes.back().tracked);

  const std::string out = test::scratchDir("session") + "/out";
  session.writeOutputs(out, nullptr, false);
  EXPECT_EQ(readTumTrajectory(out + "/trajectory.txt").size(), a.size());
  EXPECT_TRUE(std::filesystem::exists(out + "/map.plmap"));
}
