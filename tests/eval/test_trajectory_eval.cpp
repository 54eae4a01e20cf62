#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "eval/trajectory_plot.h"
#include "io/trajectory_file.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

constexpr TimeNs kT0 = 1'300'000'000LL * kNsPerSecond;  // a realistic epoch stamp

/// A smooth 3D path (helix with a drift in z) sampled at `hz`, orientation turning with it.
Trajectory helix(double seconds, double hz, TimeNs t0 = kT0) {
  Trajectory t;
  const int n = static_cast<int>(std::lround(seconds * hz)) + 1;
  for (int k = 0; k < n; ++k) {
    const double s = k / hz;
    const Eigen::Vector3d p(std::cos(0.8 * s), 0.7 * std::sin(0.8 * s), 0.1 * s);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3 * s, Eigen::Vector3d(0.2, 1, 0.1).normalized()));
    t.push_back({t0 + static_cast<TimeNs>(std::llround(s * 1e9)), SE3(q, p)});
  }
  return t;
}

SE3 someTransform() {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(1.1, Eigen::Vector3d(-0.3, 0.5, 0.8).normalized()));
  return SE3(q, Eigen::Vector3d(2.0, -3.0, 0.5));
}

}  // namespace

TEST(Stats, MatchNumpyDefinitions) {
  const Stats s = computeStats({4.0, 1.0, 3.0, 2.0});
  EXPECT_EQ(s.count, 4);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);  // mean of the middle two
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(computeStats({5.0, 1.0, 3.0}).median, 3.0);
  EXPECT_EQ(computeStats({}).count, 0);
}

TEST(Ate, RigidlyTransformedEstimateHasZeroError) {
  const Trajectory gt = helix(5.0, 100.0);
  const SE3 T = someTransform();  // the estimate lives in another world frame
  Trajectory est;
  for (const StampedPose& p : gt) est.push_back({p.t_ns + 2'000'000, T * p.T_w_c});  // 2 ms later
  const EvalResult r = evaluate(gt, est);
  EXPECT_EQ(r.ate.pairs.size(), gt.size());
  EXPECT_LT(r.ate.stats.rmse, 1e-9);
  EXPECT_LT(r.ate.stats.max, 1e-9);
  // The alignment found is the inverse of the applied transform.
  EXPECT_LT((r.ate.T_gt_est * T).translation().norm(), 1e-9);
  EXPECT_LT((r.ate.T_gt_est * T).angle(), 1e-7);
  // Relative motions are frame independent: no RPE either.
  EXPECT_GT(r.rpe.pairs, 0);
  EXPECT_LT(r.rpe.trans.max, 1e-9);
  EXPECT_LT(r.rpe.rot_deg.max, 1e-4);
}

TEST(Ate, AlternatingOffsetGivesItsMagnitude) {
  // Every ground-truth position appears twice (the camera pauses one sample); the estimate
  // is moved by +v at the first and -v at the second. The offsets have zero mean and are
  // uncorrelated with the positions, so the best alignment is the identity and every error
  // is |v|, whatever rigid transform is applied to the estimate on top.
  const Trajectory path = helix(4.0, 25.0);
  const Eigen::Vector3d v(0.03, -0.04, 0.12);  // |v| = 0.13
  const SE3 T = someTransform();
  Trajectory gt, est;
  for (size_t k = 0; k < path.size(); ++k) {
    for (int twice = 0; twice < 2; ++twice) {
      const TimeNs t = path[k].t_ns + twice * 10'000'000;  // 10 ms apart; samples are 40 ms apart
      gt.push_back({t, path[k].T_w_c});
      const SE3 moved(path[k].T_w_c.quaternion(), path[k].T_w_c.translation() + (twice ? -v : v));
      est.push_back({t, T * moved});
    }
  }
  const EvalResult r = evaluate(gt, est);
  ASSERT_EQ(r.ate.pairs.size(), gt.size());
  EXPECT_NEAR(r.ate.stats.rmse, 0.13, 1e-9);
  EXPECT_NEAR(r.ate.stats.mean, 0.13, 1e-9);
  EXPECT_NEAR(r.ate.stats.median, 0.13, 1e-9);
  EXPECT_NEAR(r.ate.stats.min, 0.13, 1e-9);
  EXPECT_NEAR(r.ate.stats.max, 0.13, 1e-9);
  EXPECT_NEAR(r.ate.stats.std, 0.0, 1e-9);
}

TEST(Ate, AStraightTrajectoryIsAligned) {
  // Collinear positions fix no rotation about their line; the ATE is still defined (0 here).
  Trajectory gt, est;
  const SE3 T = someTransform();
  for (int k = 0; k < 10; ++k) {
    const SE3 pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1 * k, 0, 0));
    gt.push_back({k * 100000000LL, pose});
    est.push_back({k * 100000000LL, T * pose});
  }
  EXPECT_LT(computeAte(gt, est, associate(gt, est, 0.02)).stats.rmse, 1e-9);
}

TEST(Rpe, ConstantVelocityErrorGivesKnownDrift) {
  // Ground truth moves along x at 1 m/s, the estimate at 1.1 m/s: 0.1 m of error per 1 s
  // window. 10 Hz for 5 s is 51 poses; windows start at i = 0..39 (i = 40 ends at the last
  // pose and is skipped, as are later ones whose closest pose is the last).
  Trajectory gt, est;
  for (int k = 0; k <= 50; ++k) {
    const TimeNs t = kT0 + k * 100'000'000LL;
    gt.push_back({t, SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1 * k, 0, 0))});
    est.push_back({t, SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.11 * k, 0, 0))});
  }
  const RpeResult r = computeRpe(gt, est, 1.0);
  EXPECT_EQ(r.pairs, 40);
  EXPECT_NEAR(r.trans.rmse, 0.1, 1e-9);
  EXPECT_NEAR(r.trans.min, 0.1, 1e-9);
  EXPECT_NEAR(r.trans.max, 0.1, 1e-9);
  EXPECT_NEAR(r.rot_deg.max, 0.0, 1e-6);

  // Over 2 s windows the drift doubles.
  const RpeResult r2 = computeRpe(gt, est, 2.0);
  EXPECT_EQ(r2.pairs, 30);
  EXPECT_NEAR(r2.trans.mean, 0.2, 1e-9);
}

TEST(Rpe, ConstantRotationRateErrorGivesKnownDrift) {
  // Both stand still; the estimate turns about its z axis at 0.05 rad/s: 0.05 rad per second.
  Trajectory gt, est;
  for (int k = 0; k <= 50; ++k) {
    const TimeNs t = kT0 + k * 100'000'000LL;
    gt.push_back({t, SE3()});
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.005 * k, Eigen::Vector3d::UnitZ()));
    est.push_back({t, SE3(q, Eigen::Vector3d::Zero())});
  }
  const RpeResult r = computeRpe(gt, est, 1.0);
  EXPECT_EQ(r.pairs, 40);
  EXPECT_NEAR(r.rot_deg.rmse, 0.05 * 180.0 / M_PI, 1e-5);
  EXPECT_NEAR(r.trans.max, 0.0, 1e-12);
}

TEST(Rpe, UsesEveryEstimatePoseAndSkipsGroundTruthGaps) {
  // The estimate at 10 Hz, ground truth at 100 Hz with a 2 s hole: windows whose ends fall
  // in the hole (more than twice the median ground-truth interval from any sample) are skipped.
  Trajectory gt, est;
  for (int k = 0; k <= 1000; ++k) {
    if (k > 400 && k < 600) continue;
    gt.push_back({kT0 + k * 10'000'000LL, SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.01 * k, 0, 0))});
  }
  for (int k = 0; k <= 100; ++k)
    est.push_back({kT0 + k * 100'000'000LL, SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1 * k, 0, 0))});
  const RpeResult r = computeRpe(gt, est, 1.0);
  // i = 0..89 have j = i + 10 (< 100, the last); the pairs with an end in (4.0, 6.0) s, i.e.
  // t_i in (4.0, 6.0) or t_j in (4.0, 6.0), are dropped: i = 31..59 (29 windows).
  EXPECT_EQ(r.pairs, 90 - 29);
  EXPECT_LT(r.trans.max, 1e-9);
}

TEST(Evaluate, StampsMoreThanMaxDifferenceApartAreNotPaired) {
  const Trajectory gt = helix(2.0, 10.0);
  Trajectory est = gt;
  for (StampedPose& p : est) p.t_ns += 30'000'000;  // 0.03 s
  try {
    evaluate(gt, est, {}, "gt.txt", "est.txt");
    FAIL() << "expected DataError";
  } catch (const DataError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("gt.txt"), std::string::npos) << msg;
    EXPECT_NE(msg.find("est.txt"), std::string::npos) << msg;
  }
  EvalOptions wide;
  wide.max_difference_s = 0.04;
  EXPECT_EQ(evaluate(gt, est, wide).ate.pairs.size(), gt.size());
}

TEST(Evaluate, AssociationIsGreedyAndUnique) {
  // Two estimate stamps near one ground-truth stamp: only the closer one is paired.
  Trajectory gt = {{kT0, SE3()}, {kT0 + kNsPerSecond, SE3()}};
  Trajectory est = {{kT0 + 12'000'000, SE3()}, {kT0 + 3'000'000, SE3()}, {kT0 + kNsPerSecond - 5'000'000, SE3()}};
  std::sort(est.begin(), est.end(), [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  const auto m = associate(gt, est, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(est[m[0].second].t_ns, kT0 + 3'000'000);
  EXPECT_EQ(m[1].first, 1u);
}

TEST(Evaluate, FewerThanThreePairsIsADataErrorNamingBothFiles) {
  const std::string dir = test::scratchDir("eval");
  Trajectory gt = helix(1.0, 10.0);
  Trajectory est(gt.begin(), gt.begin() + 2);
  for (StampedPose& p : gt) p.t_ns += 100 * kNsPerSecond;  // no overlap at all
  writeTumTrajectory(dir + "/gt.txt", gt);
  writeTumTrajectory(dir + "/est.txt", est);
  try {
    evaluateFiles(dir + "/gt.txt", dir + "/est.txt");
    FAIL() << "expected DataError";
  } catch (const DataError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir + "/gt.txt"), std::string::npos) << msg;
    EXPECT_NE(msg.find(dir + "/est.txt"), std::string::npos) << msg;
    EXPECT_NE(msg.find("overlap"), std::string::npos) << msg;
  }
  // Two pairs only.
  Trajectory gt2 = helix(1.0, 10.0);
  EXPECT_THROW(evaluate(gt2, Trajectory(gt2.begin(), gt2.begin() + 2)), DataError);
}

TEST(Evaluate, JsonHasTheDocumentedFields) {
  const Trajectory gt = helix(3.0, 30.0);
  const EvalResult r = evaluate(gt, gt);
  const std::string j = toJson(r);
  for (const char* key : {"\"pairs\"", "\"ate\"", "\"rmse\"", "\"mean\"", "\"median\"", "\"std\"", "\"min\"", "\"max\"",
                          "\"rpe\"", "\"trans_rmse\"", "\"trans_mean\"", "\"rot_rmse_deg\"", "\"rot_mean_deg\""})
    EXPECT_NE(j.find(key), std::string::npos) << key;
  EXPECT_EQ(j.front(), '{');
  EXPECT_EQ(j[j.find_last_not_of('\n')], '}');
}

TEST(Plot, RendersTheRequestedSizeAndRefusesTinyImages) {
  const Trajectory gt = helix(3.0, 30.0);
  Trajectory est = gt;
  for (size_t k = 0; k < est.size(); ++k)
    est[k].T_w_c = SE3(gt[k].T_w_c.quaternion(), gt[k].T_w_c.translation() + Eigen::Vector3d(0, 0.01 * std::sin(k), 0));
  const EvalResult r = evaluate(gt, est);
  PlotOptions o;
  o.width = 640;
  o.height = 480;
  const cv::Mat img = renderTrajectoryPlot(gt, est, r.ate, o);
  EXPECT_EQ(img.cols, 640);
  EXPECT_EQ(img.rows, 480);
  EXPECT_EQ(img.type(), CV_8UC3);
  o.width = 100;
  EXPECT_THROW(renderTrajectoryPlot(gt, est, r.ate, o), ConfigError);
}

namespace {
struct Reference {
  const char* gt;
  const char* est;
  size_t pairs;
  double ate_rmse, ate_mean, ate_median, rpe_trans_rmse, rpe_rot_rmse_deg;
};
// docs/BENCHMARK.md, "Reference figures" (the TUM benchmark's own scripts).
const Reference kReferences[] = {
    {"freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", 786, 0.013473, 0.012029, 0.011176, 0.021217,
     0.934480},
    {"fr2_desk_groundtruth.txt", "fr2_desk_ORB.txt", 2223, 0.008144, 0.007514, 0.007432, 0.007161, 0.455005},
};
}  // namespace

TEST(Reference, ReproducesBenchmarkFigures) {
  PLSLAM_REQUIRE_SHARED("data/trajectories");
  const std::string dir = test::sharedDir() + "/data/trajectories/";
  for (const Reference& ref : kReferences) {
    SCOPED_TRACE(ref.est);
    const EvalResult r = evaluateFiles(dir + ref.gt, dir + ref.est);
    EXPECT_EQ(r.ate.pairs.size(), ref.pairs);
    EXPECT_NEAR(r.ate.stats.rmse, ref.ate_rmse, 1e-5);
    EXPECT_NEAR(r.ate.stats.mean, ref.ate_mean, 1e-5);
    EXPECT_NEAR(r.ate.stats.median, ref.ate_median, 1e-5);
    EXPECT_NEAR(r.rpe.trans.rmse, ref.rpe_trans_rmse, 1e-5);
    EXPECT_NEAR(r.rpe.rot_deg.rmse, ref.rpe_rot_rmse_deg, 1e-5);
  }
}
