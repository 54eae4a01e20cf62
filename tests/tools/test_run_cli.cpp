// Runs the built `plslam run` as a user would: outputs, configuration handling, Ctrl-C.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include <opencv2/imgcodecs.hpp>

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
  ASSERT_EQ(test::runPlslam(runArgs(data, scratch + "/sparse") + " --sequential --quiet --no-dense").status, 0);
  EXPECT_NE(test::readFile(scratch + "/sparse/map_frame.yaml").find("floor_source: sparse"), std::string::npos);
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

TEST(RunCli, CtrlCStopsAndStillWritesWhatItHas) {
  const std::string scratch = test::scratchDir("runcli");
  const std::string data = syntheticFolder(scratch, 200);
  const std::string out = scratch + "/out";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string exe = test::binaryDir() + "/plslam";
    const std::string calib = data + "/camera.xml";
    execl(exe.c_str(), exe.c_str(), "run", "--dataset", data.c_str(), "--calib", calib.c_str(), "--out", out.c_str(),
          "--quiet", "--sequential", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Interrupt once tracking is under way (well before 200 frames are done: sequential mode runs at about 10-25 frames a second here).
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const std::string traj = test::readFile(out + "/trajectory.txt");
  ASSERT_FALSE(traj.empty()) << "no trajectory written after Ctrl-C";
  int lines = 0;
  for (char c : traj) lines += c == '\n';
  EXPECT_GT(lines, 2);
  EXPECT_LT(lines, 200 + 2) << "the run should have been cut short";
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
