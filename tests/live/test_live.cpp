// The live path fed by the replay grabber at camera rate: every grabbed frame is either
// processed or counted as dropped, the loop stops where asked, and a live run in
// sequential mode is reproduced exactly by `plslam run --sequential` on its recording.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "camera/camera_file.h"
#include "capture/frame_grabber.h"
#include "capture/replay_grabber.h"
#include "live/live_loop.h"
#include "support/test_support.h"
#include "synthetic_cache.h"
#include "system/run_outputs.h"
#include "system/system.h"

using namespace plslam;

namespace {

struct LiveRun {
  LiveStats live;
  RunStats run;
  Trajectory trajectory;
};

LiveRun runFake(int frames, const LiveOptions& options, bool sequential,
                const std::function<void(const LiveProgress&)>& progress = {}, int period_ms = 500,
                const std::function<bool()>& stop = {}) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  ReplayOptions ropt;
  ropt.max_frames = frames;
  ReplayGrabber grabber(dir, ropt);
  grabber.open();
  SystemOptions so;
  so.sequential = sequential;
  System slam(grabber.intrinsics(), so);
  slam.start();
  LiveRun r;
  r.live = runLive(&grabber, &slam, options, stop, progress, period_ms);
  slam.finish();
  r.run = slam.stats();
  r.trajectory = slam.trajectory();
  return r;
}

}  // namespace

TEST(LiveLoop, FakeCameraAtThirtyHertzAccountsForEveryFrame) {
  LiveOptions o;  // drop-oldest, threaded System: the real configuration
  const LiveRun r = runFake(45, o, false);
  EXPECT_EQ(r.live.grabbed, 45);
  EXPECT_EQ(r.live.processed + r.live.dropped, r.live.grabbed);
  EXPECT_EQ(r.live.stop, LiveStop::kEndOfStream);
  EXPECT_EQ(r.run.frames, r.live.processed) << "the System saw exactly the processed frames";
  // A static scene at 30 Hz: every frame the System took gets a pose, dropped ones or not.
  EXPECT_EQ(r.live.tracked, r.live.processed);
  EXPECT_EQ(static_cast<int>(r.trajectory.size()), r.live.tracked) << "a pose for every tracked frame";
  EXPECT_GT(r.run.keyframes, 0);
  const Summary tms = summarize(r.run.tracking_ms);
  std::printf("[live figures] grabbed %d processed %d dropped %d tracked %d keyframes %d; tracking %.1f ms median, "
              "%.1f p95; %.2f s\n",
              r.live.grabbed, r.live.processed, r.live.dropped, r.live.tracked, r.run.keyframes, tms.median, tms.p95,
              r.live.seconds);
}

TEST(LiveLoop, ASlowConsumerDropsTheOldestFramesAndCountsThem) {
  LiveOptions o;
  o.queue = 1;
  // The SLAM thread is made three camera periods slow per frame: frames must be dropped.
  const LiveRun r = runFake(30, o, false, [](const LiveProgress&) { std::this_thread::sleep_for(std::chrono::milliseconds(100)); }, 0);
  EXPECT_EQ(r.live.grabbed, 30);
  EXPECT_GT(r.live.dropped, 0);
  EXPECT_EQ(r.live.processed + r.live.dropped, r.live.grabbed);
  EXPECT_EQ(r.run.frames, r.live.processed);
}

TEST(LiveLoop, StopsAtTheFrameLimitOrWhenAsked) {
  LiveOptions o;
  o.drop_frames = false;
  o.max_frames = 8;
  LiveRun r = runFake(0, o, true);
  EXPECT_EQ(r.live.stop, LiveStop::kFrameLimit);
  EXPECT_EQ(r.live.grabbed, 8);
  EXPECT_EQ(r.live.processed, 8);
  EXPECT_EQ(r.live.dropped, 0) << "the blocking queue never drops";

  LiveOptions unlimited;
  unlimited.drop_frames = false;
  int polls = 0;
  r = runFake(0, unlimited, true, {}, 500, [&] { return ++polls > 5; });
  EXPECT_EQ(r.live.stop, LiveStop::kInterrupted);
  EXPECT_EQ(r.live.grabbed, 5);
}

TEST(LiveCli, SequentialLiveRunIsReproducedByRunOnItsRecording) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const std::string scratch = test::scratchDir("livecli");
  const std::string rec = scratch + "/rec", live = scratch + "/live", replay = scratch + "/replay";
  auto r = test::runPlslam("live --fake " + dir + " --max-frames 20 --sequential --record " + rec + " --out " + live +
                           " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("frames grabbed 20, processed 20, dropped 0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("recorded 20 frames"), std::string::npos) << r.output;
  const nlohmann::json stats = test::readJson(live + "/stats.json");
  EXPECT_EQ(stats.at("live_grabbed"), 20) << stats;
  r = test::runPlslam("run --dataset " + rec + " --calib " + rec + "/camera.xml --sequential --quiet --out " + replay);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string a = test::readFile(live + "/trajectory.txt"), b = test::readFile(replay + "/trajectory.txt");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b) << "live and replayed trajectories differ";
  EXPECT_EQ(test::readFile(live + "/keyframes.txt"), test::readFile(replay + "/keyframes.txt"));
}

// plslam live takes plslam run's switches (one declaration, tools/plslam/run_session.h):
// starting from a saved map and localising in it tracks every frame and leaves the map as it
// was; the replay segmenter, which needs a recorded folder's masks, is refused.
TEST(LiveCli, StartsFromASavedMapAndLocalisesInItAsRunDoes) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const std::string scratch = test::scratchDir("livecli_map");
  const std::string map_path = scratch + "/saved.plmap";
  auto r = test::runPlslam("run --dataset " + dir + " --calib " + dir + "/camera.xml --out " + scratch +
                           "/map --max-frames 30 --sequential --no-dense --quiet --save-map " + map_path);
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::runPlslam("live --fake " + dir + " --max-frames 20 --sequential --no-dense --quiet --map " + map_path +
                      " --localize --out " + scratch + "/live");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json stats = test::readJson(scratch + "/live/stats.json");
  EXPECT_EQ(stats.at("tracked"), 20) << stats;
  const nlohmann::json saved = test::readJson(scratch + "/map/stats.json");
  EXPECT_EQ(stats.at("keyframes"), saved.at("keyframes")) << "--localize makes no keyframes";
  EXPECT_EQ(stats.at("map_points"), saved.at("map_points")) << "--localize adds no map points";

  r = test::runPlslam("live --fake " + dir + " --max-frames 5 --segmenter replay --quiet --out " + scratch + "/replay");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("use plslam run"), std::string::npos) << r.output;
}

TEST(LiveCli, WithoutRealSenseLiveAndRecordSayWhyAndExitTwo) {
  if (realSenseAvailable()) GTEST_SKIP() << "this ViSP has librealsense2";
  const std::string scratch = test::scratchDir("livecli");
  for (const std::string& command : {"live --out " + scratch + "/a", "record --out " + scratch + "/b --duration 1"}) {
    const auto r = test::runPlslam(command);
    EXPECT_EQ(r.status, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("without librealsense2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("-DUSE_REALSENSE2=ON"), std::string::npos) << r.output;
  }
}
