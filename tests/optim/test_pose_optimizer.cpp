#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "optim/pose_optimizer.h"
#include "synthetic_scene.h"

using namespace plslam;
using namespace plslam::test;

namespace {

double transError(const SE3& a, const SE3& b) { return (a.translation() - b.translation()).norm(); }
double rotErrorDeg(const SE3& a, const SE3& b) { return (a.inverse() * b).angle() * 180.0 / M_PI; }

// Runs the optimiser from the truth perturbed by 5 cm / 3 deg.
PoseOnlyResult solveFromPerturbed(PoseOnlyScene& s, std::mt19937& rng, PoseOptimizerOptions options = {}) {
  s.problem.T_w_c_init = perturb(s.T_w_c_true, 0.05, 3.0, rng);
  return PoseOptimizer(options).optimize(syntheticCamera(), s.problem);
}

}  // namespace

TEST(PoseOptimizer, ExactPointsConvergeToTruth) {
  std::mt19937 rng(1);
  for (bool depth : {false, true}) {
    PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 300, 0, depth, 0.0, 0.0, rng);
    const PoseOnlyResult r = solveFromPerturbed(s, rng);
    ASSERT_TRUE(r.converged) << toString(r.status);
    EXPECT_LT(transError(r.T_w_c, s.T_w_c_true), 1e-3) << "depth " << depth;
    EXPECT_LT(rotErrorDeg(r.T_w_c, s.T_w_c_true), 0.05) << "depth " << depth;
    EXPECT_EQ(r.inliers, 300);
  }
}

TEST(PoseOptimizer, NoisyPointsAndLinesConvergeWithinMillimetres) {
  std::mt19937 rng(2);
  PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 500, 100, true, 0.5, 1.0, rng);
  const PoseOnlyResult r = solveFromPerturbed(s, rng);
  ASSERT_TRUE(r.converged) << toString(r.status);
  EXPECT_LT(transError(r.T_w_c, s.T_w_c_true), 5e-3);
  EXPECT_LT(rotErrorDeg(r.T_w_c, s.T_w_c_true), 0.2);
  // With Gaussian noise at the modelled level few observations fall beyond the 95% gate.
  EXPECT_GT(r.inliers, 0.9 * 600);
}

TEST(PoseOptimizer, LinesAloneConstrainThePose) {
  std::mt19937 rng(3);
  {
    PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 0, 40, false, 0.0, 0.0, rng);
    const PoseOnlyResult r = solveFromPerturbed(s, rng);
    ASSERT_TRUE(r.converged) << toString(r.status);
    EXPECT_LT(transError(r.T_w_c, s.T_w_c_true), 1e-3);
    EXPECT_LT(rotErrorDeg(r.T_w_c, s.T_w_c_true), 0.05);
    EXPECT_EQ(r.inliers, 40);
  }
  {
    PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 0, 100, false, 0.5, 0.0, rng);
    const PoseOnlyResult r = solveFromPerturbed(s, rng);
    ASSERT_TRUE(r.converged) << toString(r.status);
    EXPECT_LT(transError(r.T_w_c, s.T_w_c_true), 1e-2);
    EXPECT_LT(rotErrorDeg(r.T_w_c, s.T_w_c_true), 0.2);
  }
}

TEST(PoseOptimizer, GrossOutliersAreFlaggedAndThePoseStillConverges) {
  std::mt19937 rng(4);
  PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 400, 80, false, 0.5, 0.0, rng);
  std::vector<bool> corrupted_point(s.problem.points.size(), false), corrupted_line(s.problem.lines.size(), false);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (size_t i = 0; i < s.problem.points.size(); ++i)
    if (u01(rng) < 0.2) {  // 20% gross: 20-60 px away in a random direction
      const double a = u01(rng) * 2 * M_PI, d = 20 + 40 * u01(rng);
      s.problem.points[i].uv += d * Eigen::Vector2d(std::cos(a), std::sin(a));
      corrupted_point[i] = true;
    }
  for (size_t i = 0; i < s.problem.lines.size(); ++i)
    if (u01(rng) < 0.2) {  // shift the segment sideways and tilt it
      const Eigen::Vector2d dir = (s.problem.lines[i].q - s.problem.lines[i].p).normalized();
      const Eigen::Vector2d n(-dir.y(), dir.x());
      s.problem.lines[i].p += (20 + 30 * u01(rng)) * n;
      s.problem.lines[i].q -= (5 + 10 * u01(rng)) * n;
      corrupted_line[i] = true;
    }
  const PoseOnlyResult r = solveFromPerturbed(s, rng);
  ASSERT_TRUE(r.converged) << toString(r.status);
  EXPECT_LT(transError(r.T_w_c, s.T_w_c_true), 5e-3);
  EXPECT_LT(rotErrorDeg(r.T_w_c, s.T_w_c_true), 0.2);

  int missed = 0, false_alarms = 0, bad = 0, good = 0;
  for (size_t i = 0; i < corrupted_point.size(); ++i) {
    (corrupted_point[i] ? bad : good)++;
    if (corrupted_point[i] && r.point_inlier[i]) ++missed;
    if (!corrupted_point[i] && !r.point_inlier[i]) ++false_alarms;
  }
  for (size_t i = 0; i < corrupted_line.size(); ++i) {
    (corrupted_line[i] ? bad : good)++;
    if (corrupted_line[i] && r.line_inlier[i]) ++missed;
    if (!corrupted_line[i] && !r.line_inlier[i]) ++false_alarms;
  }
  ASSERT_GT(bad, 50);
  EXPECT_EQ(missed, 0) << "of " << bad << " corrupted observations";
  EXPECT_LT(false_alarms, 0.1 * good) << "of " << good << " good observations";
  EXPECT_EQ(r.inliers, good - false_alarms + missed);
}

TEST(PoseOptimizer, NoObservationsIsANonConvergedStatus) {
  PoseOnlyProblem p;
  p.T_w_c_init = pathPose(0, 5);
  const PoseOnlyResult r = PoseOptimizer().optimize(syntheticCamera(), p);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.status, OptimStatus::kNoObservations);
  EXPECT_LT(transError(r.T_w_c, p.T_w_c_init), 1e-15);
}

TEST(PoseOptimizer, EverythingBehindTheCameraIsANonConvergedStatus) {
  std::mt19937 rng(5);
  PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 100, 20, true, 0.0, 0.0, rng);
  // Turn the camera around: every landmark is now behind it.
  const SE3 flip(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())), Eigen::Vector3d::Zero());
  s.problem.T_w_c_init = s.T_w_c_true * flip;
  const PoseOnlyResult r = PoseOptimizer().optimize(syntheticCamera(), s.problem);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.status, OptimStatus::kNoValidObservations);
  EXPECT_EQ(r.inliers, 0);
  for (bool b : r.point_inlier) EXPECT_FALSE(b);
  for (bool b : r.line_inlier) EXPECT_FALSE(b);
}

TEST(PoseOptimizer, DegenerateSegmentsAreOutliersNotCrashes) {
  std::mt19937 rng(6);
  PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 0, 5, false, 0.0, 0.0, rng);
  for (auto& l : s.problem.lines) l.q = l.p;  // zero-length segments have no line
  const PoseOnlyResult r = PoseOptimizer().optimize(syntheticCamera(), s.problem);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.status, OptimStatus::kNoValidObservations);
}

TEST(PoseOptimizer, TooFewObservationsAreReported) {
  std::mt19937 rng(7);
  PoseOnlyScene s = makePoseOnlyScene(syntheticCamera(), 4, 0, false, 0.0, 0.0, rng);
  PoseOptimizerOptions options;
  options.min_inliers = 10;
  const PoseOnlyResult r = solveFromPerturbed(s, rng, options);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.status, OptimStatus::kTooFewInliers);
  EXPECT_LT(transError(r.T_w_c, s.problem.T_w_c_init), 1e-15) << "a failed call returns the initial pose";
}
