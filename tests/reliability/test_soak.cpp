// Soak and lifecycle of the threaded System.
//
// Soak: the synthetic static sequence is fed again and again for PLSLAM_SOAK_SECONDS
// (default 120 s), RSS sampled from /proc/self/status after every pass, in two ways:
//   - restarts: a new threaded System per pass (start, feed, finish, destroy); RSS after
//     the later passes must stay within kRestartBoundMb of RSS after the second pass
//     (the first passes warm up the allocator arenas, OpenCV's and Ceres' pools);
//   - continuous: one threaded System fed the same frames forward and backward (a
//     continuous camera path with continuing stamps), in a keyframe policy that makes no
//     keyframe after the first pass, so the map stops growing: RSS from the second pass
//     on must stay within kContinuousBoundMb.
// The default keyframe policy adds a keyframe at least every 20 frames however often the
// camera has been there, so the map (and RSS) grows with the run; that growth is the
// map's, not a leak, and is what the bounded-map mode takes out.
//
// Lifecycle: start then finish at once, finish while the mapper is busy, finish twice,
// feed after finish (a clear error), destruction without finish or without start.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "camera/camera_file.h"
#include "core/error.h"
#include "core/log.h"
#include "io/dataset.h"
#include "support/test_support.h"
#include "system/system.h"
#include "system/synthetic_cache.h"

using namespace plslam;

namespace {

constexpr double kRestartBoundMb = 48;     // RSS growth allowed over the restart passes after the second
constexpr double kContinuousBoundMb = 32;  // RSS growth allowed once the map has stopped growing

double rssMb() {
  std::ifstream in("/proc/self/status");
  std::string key;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;  // kB
  }
  return -1;
}

double soakSeconds() {
  const char* env = std::getenv("PLSLAM_SOAK_SECONDS");
  const double s = env && *env ? std::atof(env) : 120.0;
  return s > 0 ? s : 120.0;
}

// The first 40 frames of the synthetic static sequence the system tests render (shared cache).
struct Sequence {
  PinholeCamera camera;
  std::vector<RgbdFrame> frames;
};

const Sequence& sequence() {
  static const Sequence seq = [] {
    const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
    Sequence s;
    s.camera = loadCameraFile(dir + "/camera.xml");
    DatasetOptions options;
    options.max_frames = 40;
    TumDataset data = TumDataset::open(dir, s.camera, options);
    RgbdFrame f;
    while (data.next(&f)) s.frames.push_back(f);
    return s;
  }();
  return seq;
}

SystemOptions threaded() {
  SystemOptions o;
  o.sequential = false;
  return o;
}

// Feeds the sequence once (forward, or backward when `backward`), stamps continuing from `*t_ns`.
int feedPass(System* slam, const Sequence& seq, bool backward, TimeNs* t_ns) {
  int tracked = 0;
  const size_t n = seq.frames.size();
  for (size_t k = 0; k < n; ++k) {
    RgbdFrame f = seq.frames[backward ? n - 1 - k : k];
    *t_ns += 33'333'333;
    f.t_ns = *t_ns;
    tracked += isTracked(slam->feed(f).status);
  }
  return tracked;
}

}  // namespace

TEST(Soak, ThreadedSystemFedAgainAndAgainKeepsMemoryBounded) {
  setLogLevel(LogLevel::kError);  // relocalisation notices on every restart of the path would flood the log
  const Sequence& seq = sequence();
  ASSERT_GE(seq.frames.size(), 30u);
  const double total = soakSeconds();
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

  // Restarts: a new System every pass.
  std::vector<double> restart_rss;
  long frames_fed = 0;
  while (restart_rss.size() < 3 || elapsed() < total / 2) {
    System slam(seq.camera, threaded());
    slam.start();
    TimeNs t = 0;
    const int tracked = feedPass(&slam, seq, false, &t);
    slam.finish();
    frames_fed += static_cast<long>(seq.frames.size());
    EXPECT_EQ(tracked, static_cast<int>(seq.frames.size())) << "pass " << restart_rss.size();
    restart_rss.push_back(rssMb());
  }
  double restart_peak = 0;
  for (double r : restart_rss) restart_peak = std::max(restart_peak, r);

  // Continuous: one System, the path forward and back, no keyframe after the first pass.
  SystemOptions o = threaded();
  o.tracker.keyframe_max_frames = 1 << 30;
  o.tracker.keyframe_min_inliers = 0;
  o.tracker.keyframe_inlier_ratio = 0;
  o.tracker.keyframe_max_translation_m = 1e9;
  o.tracker.keyframe_max_rotation_deg = 1e9;
  System slam(seq.camera, o);
  slam.start();
  TimeNs t = 0;
  std::vector<double> cont_rss;
  std::vector<size_t> cont_keyframes, cont_points;
  int passes = 0;
  while (passes < 4 || elapsed() < total) {
    const int tracked = feedPass(&slam, seq, passes % 2 == 1, &t);
    frames_fed += static_cast<long>(seq.frames.size());
    EXPECT_GT(tracked, static_cast<int>(seq.frames.size()) * 9 / 10) << "continuous pass " << passes;
    ++passes;
    cont_rss.push_back(rssMb());
    const RunStats st = slam.stats();
    cont_keyframes.push_back(static_cast<size_t>(st.keyframes));
    cont_points.push_back(static_cast<size_t>(st.map_points));
  }
  slam.finish();
  double cont_peak = 0;
  for (double r : cont_rss) cont_peak = std::max(cont_peak, r);

  std::printf("soak: %.1f s, %ld frames; restarts: %zu passes, RSS %.1f MB after pass 2, %.1f MB final, %.1f MB peak; "
              "continuous: %d passes, keyframes %zu -> %zu, map points %zu -> %zu, RSS %.1f MB after pass 2, %.1f MB final, "
              "%.1f MB peak\n",
              elapsed(), frames_fed, restart_rss.size(), restart_rss[1], restart_rss.back(), restart_peak, passes,
              cont_keyframes.front(), cont_keyframes.back(), cont_points.front(), cont_points.back(), cont_rss[1],
              cont_rss.back(), cont_peak);
  EXPECT_LT(restart_rss.back() - restart_rss[1], kRestartBoundMb) << "RSS grows across System restarts";
  EXPECT_EQ(cont_keyframes.back(), cont_keyframes.front()) << "the bounded-map mode should add no keyframe";
  EXPECT_LT(cont_peak - cont_rss[1], kContinuousBoundMb) << "RSS grows while the map does not";
}

// ------------------------------------------------------------------------- lifecycle

TEST(Lifecycle, StartThenFinishAtOnce) {
  System slam(sequence().camera, threaded());
  slam.start();
  slam.finish();
  EXPECT_TRUE(slam.trajectory().empty());
  EXPECT_EQ(slam.stats().frames, 0);
}

TEST(Lifecycle, FinishWhileTheMapperIsBusyProcessesEveryQueuedKeyframe) {
  const Sequence& seq = sequence();
  SystemOptions o = threaded();
  o.mapping_queue = 64;          // let keyframes pile up
  o.tracker.keyframe_max_frames = 2;  // a keyframe every other frame: the mapper falls behind
  o.tracker.keyframe_min_frames = 1;
  System slam(seq.camera, o);
  slam.start();
  TimeNs t = 0;
  feedPass(&slam, seq, false, &t);
  slam.finish();  // returns once the queue is drained and the thread joined
  const RunStats s = slam.stats();
  EXPECT_GT(s.keyframes, 10);
  EXPECT_EQ(s.line_rate_keyframes, s.keyframes) << "every keyframe reaches the mapper before finish() returns";
  EXPECT_EQ(slam.trajectory().size(), static_cast<size_t>(s.tracked));
}

TEST(Lifecycle, FinishTwiceIsHarmless) {
  const Sequence& seq = sequence();
  System slam(seq.camera, threaded());
  slam.start();
  TimeNs t = 0;
  feedPass(&slam, seq, false, &t);
  slam.finish();
  const Trajectory once = slam.trajectory();
  EXPECT_NO_THROW(slam.finish());
  EXPECT_EQ(slam.trajectory().size(), once.size());
}

TEST(Lifecycle, FeedAfterFinishIsAClearError) {
  const Sequence& seq = sequence();
  System slam(seq.camera, threaded());
  slam.start();
  slam.feed(seq.frames[0]);
  slam.finish();
  try {
    slam.feed(seq.frames[1]);
    FAIL() << "feed after finish() was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("finish"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slam.stats().frames, 1);
}

TEST(Lifecycle, DestructionWithoutFinishJoinsTheMapper) {
  const Sequence& seq = sequence();
  for (int round = 0; round < 3; ++round) {
    System slam(seq.camera, threaded());
    slam.start();
    TimeNs t = 0;
    for (int i = 0; i < 10; ++i) {
      RgbdFrame f = seq.frames[i];
      t += 33'333'333;
      f.t_ns = t;
      slam.feed(f);
    }
  }  // destructors run with keyframes possibly still queued
  { System never_started(seq.camera, threaded()); }
  {
    System fed_without_start(seq.camera, threaded());
    EXPECT_EQ(fed_without_start.feed(seq.frames[0]).status, TrackingStatus::kInitialized) << "feed starts the System";
  }
  SUCCEED();
}
