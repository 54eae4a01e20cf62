#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "core/log.h"
#include "io/trajectory_file.h"
#include "support/test_support.h"

using namespace plslam;

TEST(TrajectoryFile, WriteReadRoundTrip) {
  const std::string path = test::scratchDir("io") + "/traj.txt";
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    t.push_back({1305031102175304000LL + i * 33'333'000LL, SE3(q, Eigen::Vector3d(0.5 * i, -1.25, 2.0 + i))});
  }
  writeTumTrajectory(path, t, "test");
  const Trajectory back = readTumTrajectory(path);
  ASSERT_EQ(back.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_EQ(back[i].t_ns, t[i].t_ns);
    EXPECT_LT((back[i].T_w_c.translation() - t[i].T_w_c.translation()).norm(), 1e-8);
    EXPECT_LT((back[i].T_w_c.inverse() * t[i].T_w_c).angle(), 1e-7);
  }
}

TEST(TrajectoryFile, BadLinesAreCountedAndSkipped) {
  setLogSink([](LogLevel, const std::string&, const std::string&) {});
  const std::string path = test::scratchDir("io") + "/traj.txt";
  std::ofstream(path) << "# comment\n"
                      << "2.0 0 0 0 0 0 0 1\n"
                      << "1.0 0 0 0 0 0 0 1\n"          // unsorted
                      << "1.5 0 0 0 0 0 0\n"            // 7 fields
                      << "1.6 nan 0 0 0 0 0 1\n"        // not finite
                      << "1.7 0 0 0 0 0 0 0\n"          // zero quaternion
                      << "2.0 9 0 0 0 0 0 1\n";         // duplicate: last kept
  TrajectoryReadReport r;
  const Trajectory t = readTumTrajectory(path, &r);
  setLogSink(nullptr);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].t_ns, kNsPerSecond);
  EXPECT_DOUBLE_EQ(t[1].T_w_c.translation().x(), 9.0);
  EXPECT_EQ(r.skipped_malformed, 1);
  EXPECT_EQ(r.skipped_nonfinite, 1);
  EXPECT_EQ(r.skipped_zero_quat, 1);
  EXPECT_EQ(r.duplicates_dropped, 1);
  EXPECT_TRUE(r.was_unsorted);
}

TEST(TrajectoryFile, MissingOrEmptyFileIsAnIoError) {
  const std::string dir = test::scratchDir("io");
  EXPECT_THROW(readTumTrajectory(dir + "/none.txt"), IoError);
  std::ofstream(dir + "/empty.txt") << "# nothing\n";
  EXPECT_THROW(readTumTrajectory(dir + "/empty.txt"), IoError);
}
