#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "optim/pose_graph.h"
#include "synthetic_scene.h"

using namespace plslam;
using namespace plslam::test;

namespace {

// n poses on a circle of radius 2 m (yaw follows the tangent), closing on the first.
std::vector<SE3> circle(int n) {
  std::vector<SE3> out;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    out.emplace_back(Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY())),
                     Eigen::Vector3d(2 * std::sin(a), 0.1 * std::sin(3 * a), 2 - 2 * std::cos(a)));
  }
  return out;
}

// Odometry edges with a systematic drift (yaw bias and scale) and some noise; the initial
// vertices are the chained odometry.
PoseGraphProblem driftingOdometry(const std::vector<SE3>& truth, std::mt19937& rng) {
  PoseGraphProblem p;
  const SE3 bias(Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
                 Eigen::Vector3d(0.005, -0.003, 0.004));
  p.vertices.push_back({truth[0], true});
  for (size_t k = 1; k < truth.size(); ++k) {
    const SE3 rel = truth[k - 1].inverse() * truth[k] * bias;
    const SE3 meas = perturb(rel, 0.002, 0.05, rng);
    p.edges.push_back({static_cast<int>(k - 1), static_cast<int>(k), meas, PoseGraphProblem::information(0.01, 0.005)});
    p.vertices.push_back({p.vertices.back().T_w_c * meas, false});
  }
  return p;
}

}  // namespace

TEST(PoseGraphOptimizer, LoopEdgeCorrectsDrift) {
  std::mt19937 rng(21);
  const std::vector<SE3> truth = circle(40);
  PoseGraphProblem p = driftingOdometry(truth, rng);
  const int last = static_cast<int>(truth.size()) - 1;
  const double drift_before = (p.vertices[last].T_w_c.translation() - truth[last].translation()).norm();
  ASSERT_GT(drift_before, 0.2) << "the test needs a visible drift";

  // Without the loop edge the odometry is already consistent: nothing moves.
  const PoseGraphResult open = PoseGraphOptimizer().optimize(p);
  ASSERT_TRUE(open.ok()) << toString(open.status);
  EXPECT_NEAR((open.T_w_c[last].translation() - truth[last].translation()).norm(), drift_before, 1e-3);

  // The loop edge: the exact relative pose of the last vertex in the first.
  p.edges.push_back({0, last, truth[0].inverse() * truth[last], PoseGraphProblem::information(0.005, 0.002)});
  const PoseGraphResult r = PoseGraphOptimizer().optimize(p);
  ASSERT_TRUE(r.ok()) << toString(r.status);
  EXPECT_LT(r.final_cost, r.initial_cost);
  const double drift_after = (r.T_w_c[last].translation() - truth[last].translation()).norm();
  EXPECT_LT(drift_after, 0.1 * drift_before) << "before " << drift_before;
  EXPECT_LT((r.T_w_c[last].inverse() * truth[last]).angle(), 0.2 * (p.vertices[last].T_w_c.inverse() * truth[last]).angle());
  // The fixed vertex did not move; the worst error along the loop shrinks too.
  EXPECT_LT((r.T_w_c[0].translation() - truth[0].translation()).norm(), 1e-12);
  double worst_before = 0, worst_after = 0;
  for (int k = 0; k <= last; ++k) {
    worst_before = std::max(worst_before, (p.vertices[k].T_w_c.translation() - truth[k].translation()).norm());
    worst_after = std::max(worst_after, (r.T_w_c[k].translation() - truth[k].translation()).norm());
  }
  EXPECT_LT(worst_after, 0.5 * worst_before);
}

TEST(PoseGraphOptimizer, ExactGraphStaysAtTheTruth) {
  const std::vector<SE3> truth = circle(12);
  PoseGraphProblem p;
  for (size_t k = 0; k < truth.size(); ++k) p.vertices.push_back({truth[k], k == 0});
  for (size_t k = 0; k + 1 < truth.size(); ++k)
    p.edges.push_back({static_cast<int>(k), static_cast<int>(k + 1), truth[k].inverse() * truth[k + 1]});
  p.edges.push_back({0, 11, truth[0].inverse() * truth[11]});
  std::mt19937 rng(22);
  for (size_t k = 1; k < truth.size(); ++k) p.vertices[k].T_w_c = perturb(truth[k], 0.05, 2.0, rng);
  const PoseGraphResult r = PoseGraphOptimizer().optimize(p);
  ASSERT_TRUE(r.ok()) << toString(r.status);
  for (size_t k = 0; k < truth.size(); ++k) {
    EXPECT_LT((r.T_w_c[k].translation() - truth[k].translation()).norm(), 1e-6) << k;
    EXPECT_LT((r.T_w_c[k].inverse() * truth[k]).angle(), 1e-6) << k;
  }
}

TEST(PoseGraphOptimizer, DegenerateInputsReturnAStatusOrThrow) {
  PoseGraphProblem p;
  p.vertices.push_back({SE3(), true});
  p.vertices.push_back({SE3(), false});
  EXPECT_EQ(PoseGraphOptimizer().optimize(p).status, OptimStatus::kNoObservations);

  p.edges.push_back({0, 5, SE3()});
  EXPECT_THROW(PoseGraphOptimizer().optimize(p), DataError);
  p.edges.back() = {0, 1, SE3(), -Eigen::Matrix<double, 6, 6>::Identity()};
  EXPECT_THROW(PoseGraphOptimizer().optimize(p), DataError);

  p.edges.back() = {0, 1, SE3()};
  p.vertices[1].fixed = true;
  EXPECT_EQ(PoseGraphOptimizer().optimize(p).status, OptimStatus::kNothingToOptimise);
}
