// Ctrl-C at any moment of `plslam run` leaves each output either absent (or the earlier
// run's, untouched) or complete, never half-written; and no temporary file behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/option_table.h"
#include "io/trajectory_file.h"
#include "mapfile/map_file.h"
#include "support/test_support.h"
#include "system/synthetic_cache.h"

using namespace plslam;
namespace fs = std::filesystem;

namespace {

const char* const kOutputs[] = {"trajectory.txt", "keyframes.txt", "sparse_map.ply", "stats.json", "config.yaml",
                                "map.plmap"};
const std::string kOld = "output of an earlier run\n";

// Empty when `path` is a complete output of its kind, else what is wrong with it.
std::string problemWith(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  const std::string text = test::readFile(path);
  if (text == kOld) return "";  // the earlier run's file, left as it was
  try {
    if (name == "trajectory.txt" || name == "keyframes.txt") {
      TrajectoryReadReport report;
      if (text.find_first_not_of("#") == std::string::npos) return "";
      const Trajectory t = parseTumTrajectory(text, path, &report);
      if (report.skipped_malformed + report.skipped_nonfinite + report.skipped_zero_quat > 0) return "a malformed line";
      if (text.back() != '\n') return "no final newline";
      (void)t;
    } else if (name == "stats.json") {
      if (!nlohmann::json::accept(text) || !nlohmann::json::parse(text).is_object()) return "not a whole JSON object";
    } else if (name == "config.yaml") {
      (void)parseYamlSubset(text, path);
    } else if (name == "sparse_map.ply") {
      std::istringstream in(text);
      std::string line;
      long vertices = -1, edges = -1, rows = 0;
      bool body = false;
      while (std::getline(in, line)) {
        if (body) ++rows;
        else if (line.rfind("element vertex ", 0) == 0) vertices = std::stol(line.substr(15));
        else if (line.rfind("element edge ", 0) == 0) edges = std::stol(line.substr(13));
        else if (line == "end_header") body = true;
      }
      if (!body || rows != vertices + edges) return "PLY body does not match its header";
    } else if (name == "map.plmap") {
      (void)parseMap(text, path);
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Interrupt, CtrlCAtAnyMomentLeavesEveryOutputAbsentOrComplete) {
  const std::string data = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const std::string scratch = test::scratchDir("interrupt");
  // Early (loading), during tracking, and late in the run.
  for (int delay_ms : {150, 1500, 4000, 8000}) {
    SCOPED_TRACE("SIGINT after " + std::to_string(delay_ms) + " ms");
    const std::string out = scratch + "/out" + std::to_string(delay_ms);
    fs::create_directories(out);
    for (const char* f : kOutputs) {
      std::FILE* fp = std::fopen((out + "/" + f).c_str(), "w");
      std::fputs(kOld.c_str(), fp);
      std::fclose(fp);
    }
    const pid_t pid = test::startPlslamRun(data, out);
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    // Finished before the signal (0), stopped by it and wrote what it had (130), or ended
    // by it before the handler was installed (nothing written yet): never anything else.
    const bool ok = (WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 130)) ||
                    (WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
    EXPECT_TRUE(ok) << "status " << status;
    for (const char* f : kOutputs) {
      const std::string path = out + "/" + f;
      if (fs::exists(path)) {
        EXPECT_EQ(problemWith(path), "") << path;
      }
    }
    for (const auto& e : fs::directory_iterator(out))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << "temporary file left: " << e.path();
  }
}

namespace {

// True once `pid` catches SIGINT (its handler is installed): /proc/PID/status, SigCgt.
bool catchesSigint(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1ULL;
  return false;
}

}  // namespace

// A user who presses Ctrl-C again while the run winds down (joins its threads, writes its
// outputs) must not cut it short: every output is written whole. (The last presses may still
// end the process by the default action once the outputs are out, as it exits.)
TEST(Interrupt, CtrlCPressedAgainWhileTheOutputsAreWrittenDoesNotCutThemShort) {
  const std::string data = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const std::string out = test::scratchDir("interrupt_again") + "/out";
  fs::create_directories(out);
  const pid_t pid = test::startPlslamRun(data, out);
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!catchesSigint(pid) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(catchesSigint(pid)) << "plslam run never installed its Ctrl-C handler";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // into the tracking
  int status = 0;
  // Ctrl-C every 10 ms until it has ended: the first stops the frames, the others come
  // while it finishes.
  while (waitpid(pid, &status, WNOHANG) == 0) {
    kill(pid, SIGINT);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE((WIFEXITED(status) && WEXITSTATUS(status) == 130) || (WIFSIGNALED(status) && WTERMSIG(status) == SIGINT))
      << "status " << status;
  for (const char* f : kOutputs) {
    const std::string path = out + "/" + f;
    ASSERT_TRUE(fs::exists(path)) << path;
    EXPECT_EQ(problemWith(path), "") << path;
  }
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << "temporary file left: " << e.path();
}
