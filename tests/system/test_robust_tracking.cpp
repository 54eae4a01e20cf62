// Tracking that does not give up: the fallbacks before "lost" (reference keyframe through
// the vocabulary, then a wider window) and relocalisation by place recognition over the
// whole map, on synthetic scenes with exact ground truth. Frames are dropped or replayed
// out of place to make the motion model wrong by a known amount.
#include <gtest/gtest.h>

#include <map>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "synth/renderer.h"
#include "synth/scene.h"
#include "synthetic_cache.h"
#include "system/system.h"

using namespace plslam;

namespace {

using Sequence = test::RenderedSequence;


Sequence render(synth::SceneKind kind, int frames, int width, int height) {
  synth::SceneOptions o;
  o.width = width;
  o.height = height;
  o.frames = frames;
  return test::renderSequence(kind, o);
}

SystemOptions sequentialNoLoop() {
  SystemOptions o;
  o.sequential = true;
  o.use_loop = false;  // keeps relocalisation the only way back
  o.dense.enabled = false;
  return o;
}

SystemOptions withoutFallbacks() {
  SystemOptions o = sequentialNoLoop();
  o.tracker.reference_fallback = false;
  o.tracker.wide_fallback_factor = 1.0;
  o.tracker.relocalisation_fallback = false;
  return o;
}

struct Fed {
  std::vector<TrackingResult> results;
  std::vector<int> scene_index;  ///< the scene frame each result is of
  std::vector<TimeNs> stamps;    ///< the stamp each frame was fed with
  RunStats stats;
  Trajectory trajectory;  ///< the System's final trajectory (after loop corrections)
};

constexpr int kBlank = -1;  ///< in a feeding order: a featureless grey frame (a covered lens)

/// Feeds scene frames `order`, in time order; `frame_period_stamps`: every frame one period
/// after the last whatever the scene's stamps (a gap then looks like one frame's motion).
Fed feed(const Sequence& seq, const std::vector<int>& order, const SystemOptions& options,
         bool frame_period_stamps = false) {
  System slam(seq.scene.camera(), options);
  slam.start();
  Fed out;
  TimeNs last_t = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    RgbdFrame f = seq.frames[order[k] == kBlank ? 0 : order[k]].toRgbdFrame();
    if (order[k] == kBlank) f.bgr = cv::Mat(f.bgr.size(), CV_8UC3, cv::Scalar(128, 128, 128));
    // The scene's stamps while they go forward (a dropped stretch keeps its real duration),
    // one frame period after the last otherwise (a replayed earlier view).
    const TimeNs next = k == 0 ? f.t_ns : last_t + 33'333'333;
    f.t_ns = order[k] != kBlank && f.t_ns > last_t && !frame_period_stamps ? f.t_ns : next;
    last_t = f.t_ns;
    out.results.push_back(slam.feed(f));
    out.scene_index.push_back(order[k]);
    out.stamps.push_back(f.t_ns);
  }
  slam.finish();
  out.stats = slam.stats();
  out.trajectory = slam.trajectory();
  return out;
}

/// Position error of result k relative to result `from` (both tracked) against the truth.
double relativeError(const Sequence& seq, const Fed& fed, size_t from, size_t k) {
  const SE3 truth = seq.scene.cameraPose(fed.scene_index[from]).inverse() * seq.scene.cameraPose(fed.scene_index[k]);
  const SE3 estimate = fed.results[from].T_w_c.inverse() * fed.results[k].T_w_c;
  return (estimate.translation() - truth.translation()).norm();
}

std::vector<int> range(int from, int to) {
  std::vector<int> v;
  for (int i = from; i < to; ++i) v.push_back(i);
  return v;
}

}  // namespace

TEST(RobustTracking, AJumpThatBreaksTheMotionModelIsTrackedByAFallback) {
  const Sequence seq = render(synth::SceneKind::kStatic, 120, 640, 480);
  // Frames 50..69 are dropped: the motion model predicts a 1-frame step where 21 happened.
  std::vector<int> order = range(0, 50);
  for (int i : range(70, 120)) order.push_back(i);
  const Fed plain = feed(seq, order, withoutFallbacks());
  ASSERT_GE(plain.stats.lost_events, 1) << "the gap must defeat the motion model, or this test proves nothing";

  const Fed fed = feed(seq, order, sequentialNoLoop());
  EXPECT_EQ(fed.stats.lost_events, 0);
  EXPECT_EQ(fed.stats.tracked, static_cast<int>(order.size()));
  const TrackingResult& after_gap = fed.results[50];
  EXPECT_TRUE(after_gap.method == TrackingMethod::kReferenceKeyframe || after_gap.method == TrackingMethod::kWideWindow)
      << toString(after_gap.method);
  EXPECT_LT(relativeError(seq, fed, 49, 50), 0.01) << "the motion across the gap";
  EXPECT_LT(relativeError(seq, fed, 49, order.size() - 1), 0.02);
}

TEST(RobustTracking, APoseThatWouldNeedAnImpossibleSpeedIsRefused) {
  const Sequence seq = render(synth::SceneKind::kStatic, 120, 640, 480);
  // The same 20-frame gap, but stamped as if one frame period had passed: the pose the
  // fallback finds is right, yet the camera would have moved at several metres a second.
  std::vector<int> order = range(0, 50);
  for (int i : range(70, 120)) order.push_back(i);
  SystemOptions no_relocalisation = sequentialNoLoop();
  no_relocalisation.tracker.relocalisation_fallback = false;  // it has no speed limit (next test)
  const Fed gated = feed(seq, order, no_relocalisation, true);
  EXPECT_FALSE(isTracked(gated.results[50].status));
  EXPECT_NE(gated.results[50].reason.find("a jump of"), std::string::npos) << gated.results[50].reason;
  SystemOptions fast_camera = no_relocalisation;
  fast_camera.tracker.max_speed_m_s = 100;
  const Fed ungated = feed(seq, order, fast_camera, true);
  EXPECT_TRUE(isTracked(ungated.results[50].status)) << ungated.results[50].reason;
}

// The last pose may itself be wrong (a walker dragged it): every attempt around it is then
// refused, and place recognition, which needs no prediction, places the frame at once, so no
// frame is lost. Stand-in for the wrong last pose: the same gap stamped one period apart.
TEST(RobustTracking, AFrameEveryPredictionFailsOnIsRelocalisedAtOnceInsteadOfLost) {
  const Sequence seq = render(synth::SceneKind::kStatic, 120, 640, 480);
  std::vector<int> order = range(0, 50);
  for (int i : range(70, 120)) order.push_back(i);
  const Fed fed = feed(seq, order, sequentialNoLoop(), true);
  EXPECT_EQ(fed.stats.lost_events, 0);
  EXPECT_EQ(fed.stats.tracked, static_cast<int>(order.size()));
  EXPECT_EQ(fed.results[50].method, TrackingMethod::kRelocalisation) << fed.results[50].reason;
  EXPECT_LT(relativeError(seq, fed, 49, 50), 0.01) << "the motion across the gap";
  EXPECT_LT(relativeError(seq, fed, 49, order.size() - 1), 0.02) << "the velocity after it starts afresh";
}

TEST(RobustTracking, ALostCameraIsRelocalisedByPlaceRecognitionFarFromTheRecentKeyframes) {
  // Round the room, then blank frames (lost), then back at the start of the lap: the
  // place is many keyframes old, out of reach of the recent keyframes.
  const Sequence seq = render(synth::SceneKind::kLoop, 300, 320, 240);
  std::vector<int> order = range(0, 160);
  const size_t first_blank = order.size();
  const int blanks = 3;
  for (int b = 0; b < blanks; ++b) order.push_back(kBlank);
  const size_t back = order.size();
  for (int i : range(5, 40)) order.push_back(i);

  SystemOptions no_vocabulary = sequentialNoLoop();
  no_vocabulary.loop.vocabulary = "/nonexistent/vocabulary.voc";
  const Fed recent_only = feed(seq, order, no_vocabulary);
  EXPECT_FALSE(isTracked(recent_only.results[back].status)) << "recent keyframes alone should not find the old place";

  const Fed fed = feed(seq, order, sequentialNoLoop());
  for (size_t k = first_blank; k < back; ++k) EXPECT_FALSE(isTracked(fed.results[k].status));
  ASSERT_EQ(fed.results[back].status, TrackingStatus::kRelocalized) << fed.results[back].reason;
  EXPECT_EQ(fed.results[back].method, TrackingMethod::kRelocalisation);
  EXPECT_LT(relativeError(seq, fed, 5, back), 0.03) << "the relocalised pose against the same view tracked before";
  for (size_t k = back; k < order.size(); ++k) EXPECT_TRUE(isTracked(fed.results[k].status)) << "frame " << k;
  ASSERT_EQ(fed.stats.recovery_frames.size(), 1u);
  EXPECT_EQ(fed.stats.recovery_frames[0], blanks);
  EXPECT_NEAR(fed.stats.recovery_s[0], blanks / 30.0, 0.01);
  EXPECT_EQ(fed.stats.methods[static_cast<int>(TrackingMethod::kRelocalisation)], 1);
}

namespace {

/// A third of a lap round the room, a covered lens for `blanks` frames, then a stretch of the
/// lap the map never saw (the far side of the room): relocalisation has nothing to find.
/// Fed one frame period apart, so the loss lasts as many periods as frames are missing.
struct UnseenAfterLoss {
  Sequence seq = render(synth::SceneKind::kLoop, 300, 320, 240);
  std::vector<int> order;
  size_t last_tracked = 0, back = 0;
  explicit UnseenAfterLoss(int blanks, int resume_at = 180, int resume_to = 240) {
    order = range(0, 91);
    last_tracked = order.size() - 1;
    for (int b = 0; b < blanks; ++b) order.push_back(kBlank);
    back = order.size();
    for (int i : range(resume_at, resume_to)) order.push_back(i);
  }
};

SystemOptions reanchorAfter(double seconds) {
  SystemOptions o = sequentialNoLoop();
  o.tracker.reanchor_after_s = seconds;
  return o;
}

}  // namespace

TEST(RobustTracking, ACameraThatCannotBeRelocalisedGoesOnFromItsLastPoseOnceTheSetTimeHasPassed) {
  const UnseenAfterLoss run(40);  // 40 frames: 1.37 s from the last tracked frame to the next textured one
  const Fed never = feed(run.seq, run.order, reanchorAfter(0), true);
  for (size_t k = run.back; k < run.order.size(); ++k)
    ASSERT_FALSE(isTracked(never.results[k].status)) << "frame " << k << ": relocalised, so this test proves nothing";

  const Fed fed = feed(run.seq, run.order, reanchorAfter(1.0), true);
  const TrackingResult& first = fed.results[run.back];
  ASSERT_EQ(first.status, TrackingStatus::kReanchored) << first.reason;
  EXPECT_EQ(first.method, TrackingMethod::kReanchor);
  EXPECT_TRUE(first.new_keyframe);
  const SE3 jump = fed.results[run.last_tracked].T_w_c.inverse() * first.T_w_c;
  EXPECT_LT(jump.translation().norm() + jump.angle(), 1e-9) << "it starts from the last tracked pose";
  for (size_t k = run.back; k < run.order.size(); ++k) EXPECT_TRUE(isTracked(fed.results[k].status)) << "frame " << k;
  // The motion after re-anchoring, against a map started afresh from the same frame (that
  // far side of the room at 320x240 drifts about 6 cm over these 2 s whichever way it starts).
  const std::vector<int> unseen_part(run.order.begin() + run.back, run.order.end());
  const Fed fresh = feed(run.seq, unseen_part, reanchorAfter(1.0), true);
  EXPECT_LT(relativeError(run.seq, fed, run.back, run.order.size() - 1),
            relativeError(run.seq, fresh, 0, unseen_part.size() - 1) + 0.01);
  EXPECT_EQ(fed.stats.reanchors, 1);
  EXPECT_EQ(fed.stats.lost_events, 1);
  EXPECT_EQ(fed.stats.relocalisations, 0);
  EXPECT_EQ(fed.stats.methods[static_cast<int>(TrackingMethod::kReanchor)], 1);
  ASSERT_EQ(fed.stats.recovery_frames.size(), 1u);
  EXPECT_EQ(fed.stats.recovery_frames[0], 40);
}

TEST(RobustTracking, ReanchoringWaitsForTheSetTimeSinceTheLastTrackedFrame) {
  // Lost for 0.4 s of blanks, then unseen views: with 1 s, re-anchored on the first textured
  // frame at least 1 s after the last tracked one, not before.
  const UnseenAfterLoss run(12);
  const Fed fed = feed(run.seq, run.order, reanchorAfter(1.0), true);
  size_t reanchored = 0;
  for (size_t k = run.back; k < run.order.size() && !reanchored; ++k)
    if (fed.results[k].status == TrackingStatus::kReanchored) reanchored = k;
  ASSERT_GT(reanchored, run.back);
  const double period_s = 33'333'333 / 1e9;
  EXPECT_GE((reanchored - run.last_tracked) * period_s, 1.0);
  EXPECT_LT((reanchored - 1 - run.last_tracked) * period_s, 1.0);
  for (size_t k = run.back; k < reanchored; ++k) EXPECT_FALSE(isTracked(fed.results[k].status)) << "frame " << k;
}

TEST(RobustTracking, ALoopClosureJoinsTheReanchoredPartToTheMapBeforeTheLoss) {
  // The rest of the first lap after the re-anchor, then the start of a second lap: the
  // loop closes onto the keyframes from before the loss, and the whole jump is taken out.
  UnseenAfterLoss run(40, 180, 300);
  for (int i : range(0, 90)) run.order.push_back(i);
  auto ateOfFinalTrajectory = [&](const Fed& fed) {
    std::map<TimeNs, int> scene_of;
    for (size_t k = 0; k < fed.stamps.size(); ++k) scene_of[fed.stamps[k]] = fed.scene_index[k];
    Trajectory truth;
    for (const auto& pose : fed.trajectory) truth.push_back({pose.t_ns, run.seq.scene.cameraPose(scene_of.at(pose.t_ns))});
    return evaluate(truth, fed.trajectory).ate.stats.rmse;
  };
  const Fed without_loop = feed(run.seq, run.order, reanchorAfter(1.0), true);
  SystemOptions with_loop = reanchorAfter(1.0);
  with_loop.use_loop = true;
  const Fed fed = feed(run.seq, run.order, with_loop, true);
  const double jumped = ateOfFinalTrajectory(without_loop), joined = ateOfFinalTrajectory(fed);
  std::printf("re-anchored after a 1.37 s loss: ATE %.4f m without loop closure, %.4f m with (%d loop(s))\n", jumped,
              joined, fed.stats.loop.accepted);
  ASSERT_EQ(fed.stats.reanchors, 1);
  ASSERT_GT(jumped, 0.1) << "the re-anchor must leave a jump, or this test proves nothing";
  ASSERT_GE(fed.stats.loop.accepted, 1);
  EXPECT_EQ(fed.trajectory.size(), without_loop.trajectory.size());
  EXPECT_LT(joined, 0.03);
}

TEST(RobustTracking, FallbackAndRelocalisationOptionsOutOfRangeAreRefusedByName) {
  const PinholeCamera camera = synth::syntheticCamera(320, 240);
  auto refused = [&](auto change, const std::string& key) {
    SystemOptions o = sequentialNoLoop();
    change(&o.tracker);
    try {
      System slam(camera, o);
      ADD_FAILURE() << key << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  refused([](TrackerOptions* t) { t->min_pnp_points = 3; }, "tracker.min_pnp_points");
  refused([](TrackerOptions* t) { t->relocalisation.max_candidates = 0; }, "tracker.relocalisation_candidates");
  refused([](TrackerOptions* t) { t->relocalisation.min_relative_score = 1.5; }, "tracker.relocalisation_min_relative_score");
  refused([](TrackerOptions* t) { t->wide_fallback_factor = -1; }, "tracker.wide_fallback_factor");
  refused([](TrackerOptions* t) { t->near_plane_m = 0; }, "tracker.near_plane_m");
  refused([](TrackerOptions* t) { t->reanchor_after_s = -1; }, "tracker.reanchor_after_s");
  EXPECT_NO_THROW(System(camera, sequentialNoLoop()));
}

namespace {

/// The fast scene (bursts up to `max_rotation_deg_s`, motion blur, exposure steps), fed in order.
Fed runFastScene(double max_rotation_deg_s, int frames, double* ate) {
  synth::SceneOptions o;
  o.width = 320;
  o.height = 240;
  o.frames = frames;
  o.fast.max_rotation_deg_s = max_rotation_deg_s;
  const Sequence seq = test::renderSequence(synth::SceneKind::kFast, o);
  const Fed fed = feed(seq, range(0, frames), sequentialNoLoop());
  Trajectory truth, estimate;
  for (size_t k = 0; k < fed.results.size(); ++k)
    if (isTracked(fed.results[k].status)) {
      truth.push_back({seq.scene.frameTime(fed.scene_index[k]), seq.scene.cameraPose(fed.scene_index[k])});
      estimate.push_back({truth.back().t_ns, fed.results[k].T_w_c});
    }
  *ate = evaluate(truth, estimate).ate.stats.rmse;
  return fed;
}

/// The longest run of untracked frames after the first second.
int longestLossAfterFirstSecond(const Fed& fed) {
  int longest = 0, current = 0;
  for (size_t k = 30; k < fed.results.size(); ++k) {
    current = isTracked(fed.results[k].status) ? 0 : current + 1;
    longest = std::max(longest, current);
  }
  return longest;
}

}  // namespace

TEST(RobustTracking, FastMotionWithBlurAndExposureStepsIsTrackedEveryFrameAfterTheFirstSecond) {
  double ate = 0;
  const Fed fed = runFastScene(180, 200, &ate);
  std::printf("fast scene 180 deg/s: %d of %d tracked, lost events %d, per-frame ATE %.4f m\n", fed.stats.tracked,
              fed.stats.frames, fed.stats.lost_events, ate);
  EXPECT_EQ(longestLossAfterFirstSecond(fed), 0);
  EXPECT_EQ(fed.stats.lost_events, 0);
  EXPECT_LT(ate, 0.03);
}

TEST(RobustTracking, AtTwoAndAHalfTimesTheRatedSpeedEveryLossIsRecoveredWithinFiveFrames) {
  double ate = 0;
  const Fed fed = runFastScene(450, 200, &ate);
  std::printf("fast scene 450 deg/s: %d of %d tracked, lost events %d, relocalisations %d, per-frame ATE %.4f m\n",
              fed.stats.tracked, fed.stats.frames, fed.stats.lost_events, fed.stats.relocalisations, ate);
  ASSERT_GE(fed.stats.lost_events, 1) << "no loss to recover from: this test would prove nothing";
  EXPECT_LE(longestLossAfterFirstSecond(fed), 5);
  EXPECT_EQ(fed.stats.relocalisations, fed.stats.lost_events);
  EXPECT_TRUE(isTracked(fed.results.back().status));
}
