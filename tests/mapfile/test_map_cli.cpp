// plslam run --save-map / --map / --localize from the command line, and the map a Ctrl-C
// leaves behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "../system/synthetic_cache.h"
#include "core/error.h"
#include "mapfile/container.h"
#include "mapfile/map_file.h"
#include "support/test_support.h"

using namespace plslam;
namespace fs = std::filesystem;

TEST(MapCli, SaveMapThenLocalizeLeavesTheMapUnchanged) {
  const std::string data = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const std::string scratch = test::scratchDir("mapcli");
  const std::string map_path = scratch + "/saved.plmap";
  auto r = test::runPlslam("run --dataset " + data + " --calib " + data + "/camera.xml --out " + scratch +
                           "/map --max-frames 30 --sequential --quiet --save-map " + map_path);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(fs::exists(scratch + "/map/map.plmap")) << "--save-map replaces the default place";
  const LoadedMap saved = loadMap(map_path);
  EXPECT_GT(saved.map.keyframes().size(), 0u);
  EXPECT_NE(saved.config_yaml.find("min_inliers"), std::string::npos) << "the run's configuration is kept";

  // No --calib: the camera comes from the map.
  r = test::runPlslam("run --dataset " + data + " --map " + map_path + " --localize --out " + scratch +
                      "/loc --max-frames 30 --sequential --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("tracked 30 (100.0%)"), std::string::npos) << r.output;
  // The default map output, and the map itself unchanged (the configuration is the same).
  EXPECT_EQ(test::readFile(scratch + "/loc/map.plmap"), test::readFile(map_path));
}

TEST(MapCli, BadMapArgumentsAreRefusedWithTheReason) {
  const std::string scratch = test::scratchDir("mapcli_bad");
  auto r = test::runPlslam("run --dataset x --calib y --out " + scratch + "/o --localize");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--localize needs --map"), std::string::npos) << r.output;
  r = test::runPlslam("run --dataset x --out " + scratch + "/o --map " + scratch + "/none.plmap");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find(scratch + "/none.plmap: cannot open"), std::string::npos) << r.output;
  r = test::runPlslam("run --dataset x --out " + scratch + "/o");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--calib"), std::string::npos) << r.output;
}

TEST(MapCli, CtrlCLeavesACompleteMap) {
  const std::string data = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const std::string out = test::scratchDir("mapcli_sigint") + "/out";
  const pid_t pid = test::startPlslamRun(data, out, {"--sequential"});
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  const int code = WEXITSTATUS(status);
  EXPECT_TRUE(code == 130 || code == 0) << code;
  // Either no outputs (interrupted before anything was tracked) or a map that loads whole.
  if (fs::exists(out + "/trajectory.txt")) {
    const LoadedMap m = loadMap(out + "/" + kDefaultMapFileName);
    EXPECT_GT(m.map.keyframes().size(), 0u);
  }
  for (const auto& e : fs::directory_iterator(fs::path(out).parent_path())) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "temporary file left: " << e.path();
  }
  if (fs::exists(out)) {
    for (const auto& e : fs::directory_iterator(out))
      EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "temporary file left: " << e.path();
  }
}
