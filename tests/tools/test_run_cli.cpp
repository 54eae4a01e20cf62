// Runs the built `plslam run` as a user would: outputs, configuration handling, Ctrl-C.
#include <gtest/gtest.h>
#include <signal.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "core/map_frame.h"
#include "io/trajectory_file.h"
#include "support/test_support.h"

using namespace plslam;
namespace fs = std::filesystem;

namespace {

// A short synthetic sequence written once per test (40 frames render in seconds).
std::string syntheticFolder(const std::string& scratch, int frames) {
  const std::string dir = scratch + "/data";
  const auto r = test::runPlslam("synth --scene static --frames " + std::to_string(frames) + " --out " + dir);
  EXPECT_EQ(r.status, 0) << r.output;
  return dir;
}

std::string runArgs(const std::string& data, const std::string& out) {
  return "run --dataset " + data + " --calib " + data + "/camera.xml --out " + out;
}

}  // namespace

TEST(RunCli, WritesEveryOutputAndTheAte) {
  const std::string scratch = test::scratchDir("runcli");
  const std::string data = syntheticFolder(scratch, 30);
  const auto r = test::runPlslam(runArgs(data, scratch + "/out") + " --sequential --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("ATE RMSE"), std::string::npos) << r.output;
  for (const char* f : {"trajectory.txt", "trajectory_map.txt", "keyframes.txt", "map_frame.yaml", "sparse_map.ply",
                        "stats.json", "config.yaml", "octomap.bt"})
    EXPECT_TRUE(fs::exists(scratch + "/out/" + f)) << f;
  EXPECT_FALSE(fs::exists(scratch + "/out/trajectory_base.txt")) << "only with a camera-to-base transform";
  const nlohmann::json stats = test::readJson(scratch + "/out/stats.json");
  EXPECT_EQ(stats.at("frames"), 30) << stats;
  EXPECT_TRUE(stats.at("ate_rmse_m").is_number()) << stats;
  // The effective configuration reproduces the run when given back.
  const auto again = test::runPlslam(runArgs(data, scratch + "/out2") + " --quiet --config " + scratch + "/out/config.yaml");
  EXPECT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(test::readFile(scratch + "/out/trajectory.txt"), test::readFile(scratch + "/out2/trajectory.txt"));
}

// One map frame for a map's outputs: the run's (from the dense floor), the same again from
// `plslam export` of its map file; without dense clouds it comes from the map points.
TEST(RunCli, RunAndExportShareTheMapFrame) {
  const std::string scratch = test::scratchDir("runcli_frame");
  const std::string data = syntheticFolder(scratch, 30);
  ASSERT_EQ(test::runPlslam(runArgs(data, scratch + "/out") + " --sequential --quiet").status, 0);
  const std::string frame = test::readFile(scratch + "/out/map_frame.yaml");
  EXPECT_NE(frame.find("floor_source: dense"), std::string::npos) << frame;
  const auto r = test::runPlslam("export --map " + scratch + "/out/map.plmap --out " + scratch + "/exp --octomap --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("from the map file"), std::string::npos) << r.output;
  EXPECT_EQ(test::readFile(scratch + "/exp/map_frame.yaml"), frame);
  // export --config: a misspelt dense key is refused, naming it and the file; other sections
  // (a run's whole configuration) are not export's business.
  const std::string cfg = scratch + "/export.yaml";
  std::ofstream(cfg) << "tracker:\n  min_inliers: 12\ndense:\n  fused_voxl_m: 0.02\n";
  const auto bad = test::runPlslam("export --map " + scratch + "/out/map.plmap --out " + scratch + "/exp2 --octomap --quiet --config " + cfg);
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("dense.fused_voxl_m"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find(cfg), std::string::npos) << bad.output;
  std::ofstream(cfg) << "tracker:\n  min_inliers: 12\ndense:\n  fused_voxel_m: 0.02\n";
  const auto good = test::runPlslam("export --map " + scratch + "/out/map.plmap --out " + scratch + "/exp2 --octomap --quiet --config " + cfg);
  EXPECT_EQ(good.status, 0) << good.output;
  ASSERT_EQ(test::runPlslam(runArgs(data, scratch + "/sparse") + " --sequential --quiet --no-dense").status, 0);
  EXPECT_NE(test::readFile(scratch + "/sparse/map_frame.yaml").find("floor_source: sparse"), std::string::npos);
}

// The maps while running: updated during the run (dense.live_every_*), counted in
// stats.json; both keys 0 leave the dense products to the end.
TEST(RunCli, MapsAreUpdatedWhileRunningUnlessBothPeriodsAreZero) {
  const std::string scratch = test::scratchDir("runcli_live_maps");
  const std::string data = syntheticFolder(scratch, 60);
  const auto config = [&](const std::string& name, const char* text) {
    FILE* f = std::fopen((scratch + "/" + name).c_str(), "w");
    std::fputs(text, f);
    std::fclose(f);
    return scratch + "/" + name;
  };
  // At the default nice 19 the maps thread can get no CPU at all while ctest runs other
  // tests on both cores (seen once: one update only): this test is about the updates.
  const std::string every =
      config("every.yaml", "dense:\n  live_every_keyframes: 1\n  live_every_s: 0\n  live_nice: 0\n");
  const auto r = test::runPlslam(runArgs(data, scratch + "/on") + " --sequential --quiet --log-level info --config " + every);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("live maps: update 2 "), std::string::npos) << r.output;
  const std::string stats = test::readFile(scratch + "/on/stats.json");
  const size_t at = stats.find("\"live_map_updates\": ");
  ASSERT_NE(at, std::string::npos) << stats;
  EXPECT_GE(std::atoi(stats.c_str() + at + 20), 2) << stats;
  EXPECT_TRUE(fs::exists(scratch + "/on/grid.yaml"));

  const std::string off = config("off.yaml", "dense:\n  live_every_keyframes: 0\n  live_every_s: 0\n");
  const auto r2 = test::runPlslam(runArgs(data, scratch + "/off") + " --sequential --quiet --log-level info --config " + off);
  ASSERT_EQ(r2.status, 0) << r2.output;
  EXPECT_EQ(r2.output.find("live maps: update"), std::string::npos) << r2.output;
  EXPECT_EQ(test::readFile(scratch + "/off/stats.json").find("live_map_updates"), std::string::npos);
  EXPECT_TRUE(fs::exists(scratch + "/off/grid.yaml")) << "the end still writes the products";
}

TEST(RunCli, BadConfigurationIsRefusedNamingTheKey) {
  const std::string scratch = test::scratchDir("runcli");
  const std::string cfg = scratch + "/bad.yaml";
  FILE* f = std::fopen(cfg.c_str(), "w");
  std::fputs("tracker:\n  min_inlierz: 5\n", f);
  std::fclose(f);
  auto r = test::runPlslam("run --dataset x --calib y --out z --config " + cfg + " --print-config");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("tracker.min_inlierz"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(cfg), std::string::npos) << r.output;
  r = test::runPlslam("run --dataset /nonexistent --calib " + test::sourceDir() + "/calib/tum_freiburg1.xml --out " + scratch + "/o");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("/nonexistent"), std::string::npos) << r.output;
  r = test::runPlslam("run --dataset x --calib y");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
}

TEST(RunCli, SegmenterSwitchOverridesTheConfigKey) {
  const std::string scratch = test::scratchDir("runcli");
  const std::string cfg = scratch + "/segmenter.yaml";
  FILE* f = std::fopen(cfg.c_str(), "w");
  std::fputs("segmenter:\n  backend: yolo\n  model: /nonexistent/seg.onnx\n", f);
  std::fclose(f);
  const std::string base = "run --dataset x --calib y --out z --print-config --config " + cfg;
  auto r = test::runPlslam(base);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("backend: \"yolo\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("model: \"/nonexistent/seg.onnx\""), std::string::npos) << r.output;
  r = test::runPlslam(base + " --segmenter none");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("backend: \"none\""), std::string::npos) << r.output;
  r = test::runPlslam(base + " --segmenter /other/seg.onnx");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("model: \"/other/seg.onnx\""), std::string::npos) << r.output;

  f = std::fopen(cfg.c_str(), "w");
  std::fputs("segmenter:\n  backend: maskrcnn\n", f);
  std::fclose(f);
  r = test::runPlslam(base);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("segmenter.backend"), std::string::npos) << r.output;
}

namespace {

/// Reads `fd` until a line containing `marker` is complete (or EOF, or `timeout_s`); returns
/// that line (empty when none came).
std::string waitForLine(int fd, const std::string& marker, double timeout_s) {
  std::string buffer;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    char c;
    if (read(fd, &c, 1) != 1) break;
    if (c != '\n') {
      buffer += c;
      continue;
    }
    if (buffer.find(marker) != std::string::npos) return buffer;
    buffer.clear();
  }
  return "";
}

}  // namespace

TEST(RunCli, CtrlCStopsAndStillWritesWhatItHas) {
  const std::string scratch = test::scratchDir("runcli");
  const std::string data = syntheticFolder(scratch, 200);
  const std::string out = scratch + "/out";
  int err[2];
  ASSERT_EQ(pipe(err), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    dup2(err[1], STDERR_FILENO);
    close(err[0]);
    const std::string exe = test::binaryDir() + "/plslam";
    const std::string calib = data + "/camera.xml";
    execl(exe.c_str(), exe.c_str(), "run", "--dataset", data.c_str(), "--calib", calib.c_str(), "--out", out.c_str(),
          "--sequential", "--no-dense", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(err[1]);
  // Interrupt once tracking is under way: the first progress line says how far it got.
  const std::string progress = waitForLine(err[0], "[run] frame ", 120);
  int done = 0, total = 0, tracked = 0;
  const bool parsed = std::sscanf(progress.c_str(), "[run] frame %d/%d tracked %d", &done, &total, &tracked) == 3;
  kill(pid, SIGINT);
  waitForLine(err[0], "\x01", 60);  // no such line: reads to EOF, so the child never blocks on a full pipe
  close(err[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(parsed) << "no progress line: '" << progress << "'";
  ASSERT_LT(done, 200) << "the run ended before the interrupt; this test proves nothing";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  Trajectory written = readTumTrajectory(out + "/trajectory.txt");
  EXPECT_GE(static_cast<int>(written.size()), tracked) << "every frame tracked before the interrupt is written";
  EXPECT_LT(written.size(), 200u) << "the run was cut short";
  EXPECT_TRUE(fs::exists(out + "/stats.json"));
}

TEST(RunCli, ProgressInALogIsPlainLinesEndingWithTheLastState) {
  // Captured output is a pipe, not a terminal: no carriage returns, and the final count.
  const std::string scratch = test::scratchDir("runcli");
  const std::string data = syntheticFolder(scratch, 30);
  const auto r = test::runPlslam(runArgs(data, scratch + "/out") + " --sequential --no-dense");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[run] frame 30/30"), std::string::npos) << r.output;
}

TEST(RunCli, MasksInAnotherFormatAreIgnoredUnlessReplayIsAsked) {
  // Binary 8-bit masks (what ../shared/tools/make_walkers.py writes) over the 16-bit
  // instance masks: only --segmenter replay reads masks/, and it refuses them by name.
  const std::string scratch = test::scratchDir("runcli_masks");
  const std::string data = syntheticFolder(scratch, 20);
  for (const auto& entry : fs::directory_iterator(data + "/masks"))
    if (entry.path().extension() == ".png") {
      cv::Mat eight(cv::Size(4, 4), CV_8UC1, cv::Scalar(255));
      ASSERT_TRUE(cv::imwrite(entry.path().string(), eight));
    }
  const auto plain = test::runPlslam(runArgs(data, scratch + "/out") + " --sequential --no-dense");
  ASSERT_EQ(plain.status, 0) << plain.output;
  EXPECT_NE(plain.output.find("[run] frame 20/20"), std::string::npos) << plain.output;
  const auto replay = test::runPlslam(runArgs(data, scratch + "/out2") + " --sequential --no-dense --segmenter replay");
  EXPECT_NE(replay.status, 0);
  EXPECT_NE(replay.output.find("16-bit"), std::string::npos) << replay.output;
}

// plslam run --base: the map frame's origin is on the floor below the base at the first
// frame, x its forward direction, and trajectory_base.txt holds the base's poses in it.
// The mounting: a camera 0.10 m ahead of the base origin and 0.20 m above it, looking along
// the base's x; the scene's camera stands about 1.5 m above its floor, pitched down.
TEST(RunCli, BaseFileWritesTheBaseTrajectoryInTheMapFrameBelowTheBase) {
  const std::string scratch = test::scratchDir("runcli_base");
  const std::string data = syntheticFolder(scratch, 30);
  const SE3 T_b_c(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(0.10, 0.0, 0.20));
  std::ofstream(scratch + "/base.yaml") << "format: plslam_camera_to_base 1\nparent_frame: base\nchild_frame: camera\n"
                                           "translation: [0.10, 0, 0.20]\nrotation: [-0.5, 0.5, -0.5, 0.5]\n";
  const auto r = test::runPlslam(runArgs(data, scratch + "/out") + " --sequential --quiet --base " + scratch + "/base.yaml");
  ASSERT_EQ(r.status, 0) << r.output;
  const MapFrame frame = parseMapFrameYaml(test::readFile(scratch + "/out/map_frame.yaml"), "map_frame.yaml");
  EXPECT_EQ(frame.origin, "base");
  const Trajectory camera = readTumTrajectory(scratch + "/out/trajectory.txt");
  const Trajectory base = readTumTrajectory(scratch + "/out/trajectory_base.txt");
  ASSERT_EQ(base.size(), camera.size());
  ASSERT_GT(base.size(), 20u);
  for (size_t i = 0; i < base.size(); ++i) {
    const SE3 expected = frame.T_map_world * camera[i].T_w_c * T_b_c.inverse();
    EXPECT_EQ(base[i].t_ns, camera[i].t_ns);
    EXPECT_LT((base[i].T_w_c.translation() - expected.translation()).norm(), 1e-4) << i;
    EXPECT_LT((base[i].T_w_c.inverse() * expected).angle(), 1e-4) << i;
  }
  // At the first frame the base is straight above the origin, heading along x.
  const SE3& b0 = base.front().T_w_c;
  EXPECT_NEAR(b0.translation().x(), 0.0, 1e-4);
  EXPECT_NEAR(b0.translation().y(), 0.0, 1e-4);
  const Eigen::Vector3d forward = b0.rotation().col(0);
  EXPECT_NEAR(std::atan2(forward.y(), forward.x()), 0.0, 1e-4);
  // Its height above the floor: the truth's (the scene's floor is z = 0), within what the
  // floor of a 30-frame SLAM run gives (2 cm low here, with or without --base; the exact
  // truth is MapFrame.KnownMountingPutsTheOriginBelowTheBase... on ground-truth poses).
  const Trajectory truth = readTumTrajectory(data + "/groundtruth.txt");
  const SE3 T_scene_b0 = truth.front().T_w_c * T_b_c.inverse();
  std::printf("base origin %.4f m above the floor at the first frame, true %.4f m\n", b0.translation().z(),
              T_scene_b0.translation().z());
  EXPECT_NEAR(b0.translation().z(), T_scene_b0.translation().z(), 0.03);
}
