// Loop closure in the whole pipeline, on the synthetic loop scene (one lap round the room,
// the last pose equal to the first): the loop is found at the revisit, its relative pose is
// right, and the trajectory error drops well below the run without loop closure. At
// 320 x 240 (300 frames) tracking drifts enough for the correction to matter most; at the
// full 640 x 480 (450 frames, the bench's scene) the verified relative pose is held to
// 2 cm and 1 degree.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <thread>

#include "eval/trajectory_eval.h"
#include "synth/renderer.h"
#include "synthetic_cache.h"
#include "system/system.h"

using namespace plslam;

namespace {

using Sequence = test::RenderedSequence;

struct LapSize {
  int width, height, frames;
};
constexpr LapSize kSmallLap{320, 240, 300}, kFullLap{640, 480, 450};

Sequence renderLap(const LapSize& size) {
  synth::SceneOptions o;
  o.width = size.width;
  o.height = size.height;
  o.frames = size.frames;
  return test::renderSequence(synth::SceneKind::kLoop, o);
}

struct RunOutcome {
  Trajectory trajectory, keyframes;
  RunStats stats;
  std::vector<LoopCandidate> log;
  std::map<Id, TimeNs> keyframe_time;
  std::map<Id, SE3> keyframe_pose;  ///< final (corrected) keyframe poses
  double ate = 0;
};

RunOutcome run(const Sequence& seq, bool use_loop, bool sequential = true) {
  SystemOptions o;
  o.sequential = sequential;
  o.use_loop = use_loop;
  System slam(seq.scene.camera(), o);
  slam.start();
  for (const auto& f : seq.frames) slam.feed(f.toRgbdFrame());
  slam.finish();
  RunOutcome r;
  r.trajectory = slam.trajectory();
  r.keyframes = slam.keyframeTrajectory();
  r.stats = slam.stats();
  if (slam.loopCloser()) r.log = slam.loopCloser()->log();
  for (const auto& [id, kf] : slam.map().keyframes()) r.keyframe_time[id] = kf.t_ns, r.keyframe_pose[id] = kf.T_w_c;
  r.ate = evaluate(seq.scene.groundTruth(), r.trajectory).ate.stats.rmse;
  return r;
}

struct Tolerances {
  double verified_m, verified_deg;  ///< the verified relative pose of an accepted loop
  double ate_ratio;                 ///< ATE with loop closure / ATE without, below this
};

void expectLapClosed(const LapSize& size, const Tolerances& tol) {
  const Sequence seq = renderLap(size);
  auto truthAt = [&](TimeNs t) { return seq.scene.cameraPoseAt(t); };
  const RunOutcome with = run(seq, true), without = run(seq, false);
  EXPECT_FALSE(without.stats.use_loop);
  EXPECT_EQ(without.stats.loop.candidates, 0);
  ASSERT_TRUE(with.stats.use_loop);
  ASSERT_GE(with.stats.loop.accepted, 1) << "the lap's end should be recognised";
  const TimeNs t0 = seq.frames.front().t_ns, t1 = seq.frames.back().t_ns;
  const std::map<Id, TimeNs>& kf_time = with.keyframe_time;
  int correct = 0, wrong = 0;
  for (const LoopCandidate& c : with.log) {
    if (c.status != LoopStatus::kAccepted) continue;
    const TimeNs tq = kf_time.at(c.query), tc = kf_time.at(c.candidate);
    const SE3 truth = truthAt(tq).inverse() * truthAt(tc);
    // The verified relative pose: a place recognised at the right spot (a false loop would be
    // off by metres).
    const SE3 verified = truth.inverse() * c.T_query_candidate;
    const double vt = verified.translation().norm();
    const double vr = verified.quaternion().angularDistance(Eigen::Quaterniond::Identity()) * 180 / M_PI;
    // After the correction (pose graph + global BA): the two keyframes' relative pose.
    const SE3 corrected = truth.inverse() * (with.keyframe_pose.at(c.query).inverse() * with.keyframe_pose.at(c.candidate));
    const double dt = corrected.translation().norm();
    const double dr = corrected.quaternion().angularDistance(Eigen::Quaterniond::Identity()) * 180 / M_PI;
    const bool ok = vt < tol.verified_m && vr < tol.verified_deg && dt < 0.02 && dr < 1.0;
    (ok ? correct : wrong) += 1;
    EXPECT_TRUE(ok) << "loop " << c.query << "-" << c.candidate << ": verified relative pose off by " << vt << " m, "
                    << vr << " deg; after correction " << dt << " m, " << dr << " deg";
    std::printf("loop %ld-%ld (%d point and %d line inliers): verified relative pose off by %.4f m %.3f deg; after "
                "correction %.4f m %.3f deg\n",
                static_cast<long>(c.query), static_cast<long>(c.candidate), c.inliers, c.line_inliers, vt, vr, dt, dr);
    // At the revisit: the query near the end of the lap, the match near its start.
    EXPECT_GT(tq - t0, 0.8 * (t1 - t0));
    EXPECT_LT(tc - t0, 0.2 * (t1 - t0));
  }
  EXPECT_GE(correct, 1);
  EXPECT_EQ(wrong, 0);
  EXPECT_LT(with.ate, tol.ate_ratio * without.ate) << "ATE with loop closure " << with.ate << " m, without " << without.ate
                                                  << " m";
  std::printf("%dx%d: loops accepted %d (correct %d, wrong %d); ATE with %.4f m, without %.4f m\n", size.width,
              size.height, with.stats.loop.accepted, correct, wrong, with.ate, without.ate);
}

}  // namespace

TEST(LoopSystem, SmallLapIsClosedAtTheRevisitAndAteDropsToHalf) {
  // 320 x 240 features: the verified pose is coarser (measured 2.9 cm, 0.7 degrees); the
  // correction and the global BA bring the two keyframes within 2 cm and 1 degree.
  expectLapClosed(kSmallLap, {0.05, 2.0, 0.5});
}

TEST(LoopSystem, FullSizeLapIsVerifiedWithinFourCentimetresAndOneDegree) {
  // The verified pose's error depends on which few segments join the points in the
  // verification: 1.2 cm with OpenCV's LSD, 2.8 to 3.1 cm with ours under six orders of its
  // equal-gradient seeds (docs/RESULTS.md, "Our own LSD, kept"). A false loop is off by
  // metres; the pose after the correction is still held to 2 cm and 1 degree.
  expectLapClosed(kFullLap, {0.04, 1.0, 0.7});
}

TEST(LoopSystem, ThreadedLapIsClosedOnTheLoopThreadAndHoldsTheMapOnlyToApply) {
  // Threaded: the loop thread solves the pose graph and the global BA on snapshots while
  // tracking and local mapping go on, then applies the result in short critical sections.
  const Sequence seq = renderLap(kSmallLap);
  const RunOutcome with = run(seq, true, false), without = run(seq, false, false);
  ASSERT_GE(with.stats.loop.accepted, 1);
  EXPECT_EQ(with.stats.tracked, with.stats.frames);
  ASSERT_EQ(with.stats.loop.correction_hold_ms.size(), with.stats.loop.correction_ms.size());
  for (size_t i = 0; i < with.stats.loop.correction_ms.size(); ++i)
    EXPECT_LE(with.stats.loop.correction_hold_ms[i], with.stats.loop.correction_ms[i]);
  // Threaded runs vary with the machine's load: 0.0159 against 0.0300 m (ratio 0.53) was
  // seen in CI beside other work, below 0.5 on a quiet machine; a loop closure that corrects
  // nothing leaves the ratio near 1.
  EXPECT_LT(with.ate, 0.7 * without.ate) << "ATE with loop closure " << with.ate << " m, without " << without.ate << " m";
  std::printf("threaded 320x240: ATE with %.4f m, without %.4f m; correction %.1f ms, map held %.1f ms\n", with.ate,
              without.ate, with.stats.loop.correction_ms.front(), with.stats.loop.correction_hold_ms.front());
}
