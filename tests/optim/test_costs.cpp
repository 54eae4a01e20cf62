// The residuals themselves: zero at the truth, the documented geometry, and Jacobians (autodiff
// through the pose manifold) against central numeric differences.
#include <gtest/gtest.h>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <utility>

#include "core/error.h"
#include "optim/cost_functions.h"
#include "optim/measurement.h"
#include "synthetic_scene.h"

using namespace plslam;
using namespace plslam::optim_internal;
using namespace plslam::test;

namespace {

Intrinsics K() {
  const PinholeCamera c = syntheticCamera();
  return {c.fx, c.fy, c.cx, c.cy};
}

// Fails the test (not just prints) when the Jacobians of `cost` at `params`, taken in the
// tangent space of each block's manifold (null = Euclidean), differ from central numeric
// differences through the manifold's Plus: |analytic - numeric| <= 1e-5 * max(1, |numeric|).
void expectJacobiansMatchNumeric(const ceres::CostFunction& cost, const std::vector<const ceres::Manifold*>& manifolds,
                                 const std::vector<double*>& params) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  ASSERT_EQ(sizes.size(), params.size());
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(sizes.size());
  std::vector<double*> jac_ptrs;
  for (size_t b = 0; b < sizes.size(); ++b) {
    J[b].resize(nr, sizes[b]);
    jac_ptrs.push_back(J[b].data());
  }
  Eigen::VectorXd r0(nr);
  ASSERT_TRUE(cost.Evaluate(params.data(), r0.data(), jac_ptrs.data()));
  for (size_t b = 0; b < sizes.size(); ++b) {
    const ceres::Manifold* m = manifolds[b];
    const int ambient = sizes[b];
    const int tangent = m ? m->TangentSize() : ambient;
    Eigen::MatrixXd plus_jac = Eigen::MatrixXd::Identity(ambient, tangent);
    if (m) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> pj(ambient, tangent);
      ASSERT_TRUE(m->PlusJacobian(params[b], pj.data()));
      plus_jac = pj;
    }
    const Eigen::MatrixXd analytic = J[b] * plus_jac;
    const std::vector<double> x0(params[b], params[b] + ambient);
    for (int t = 0; t < tangent; ++t) {
      const double h = 1e-6;
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(tangent);
      Eigen::VectorXd rp(nr), rm(nr);
      for (int sign : {+1, -1}) {
        delta[t] = sign * h;
        std::vector<double> x(ambient);
        if (m)
          ASSERT_TRUE(m->Plus(x0.data(), delta.data(), x.data()));
        else
          for (int i = 0; i < ambient; ++i) x[i] = x0[i] + delta[i];
        std::copy(x.begin(), x.end(), params[b]);
        ASSERT_TRUE(cost.Evaluate(params.data(), (sign > 0 ? rp : rm).data(), nullptr));
      }
      std::copy(x0.begin(), x0.end(), params[b]);
      const Eigen::VectorXd numeric = (rp - rm) / (2 * h);
      for (int i = 0; i < nr; ++i)
        EXPECT_NEAR(analytic(i, t), numeric[i], 1e-5 * std::max(1.0, std::abs(numeric[i])))
            << "block " << b << " residual " << i << " tangent direction " << t;
    }
  }
}

}  // namespace

TEST(OptimCosts, NormalisedLineGivesSignedPixelDistance) {
  Eigen::Vector3d l;
  ASSERT_TRUE(normalisedLine({10, 10}, {110, 10}, &l));  // the row v = 10
  EXPECT_NEAR(std::abs(l.dot(Eigen::Vector3d(50, 13, 1))), 3.0, 1e-12);
  EXPECT_NEAR(l.dot(Eigen::Vector3d(-400, 10, 1)), 0.0, 1e-12);
  EXPECT_FALSE(normalisedLine({5, 5}, {5, 5}, &l));
}

TEST(OptimCosts, MeasurementModelSigmas) {
  MeasurementModel m;
  EXPECT_NEAR(m.pixelSigma(0), 1.0, 1e-15);
  EXPECT_NEAR(m.pixelSigma(2), 1.44, 1e-12);
  EXPECT_NEAR(m.depthSigma(2.0), 0.0015 * 4.0, 1e-15);
  EXPECT_FALSE(m.hasDepth(std::nan("")));
  EXPECT_FALSE(m.hasDepth(0.0));
  EXPECT_TRUE(m.hasDepth(1.0));
  m.use_depth = false;
  EXPECT_FALSE(m.hasDepth(1.0));
  m.scale_factor = 0.5;
  EXPECT_THROW(m.validate(), ConfigError);
}

TEST(OptimCosts, ResidualsVanishAtTheTruthAndMeasurePixels) {
  const SE3 T_w_c = pathPose(2, 5);
  double pose[kPoseSize];
  poseToBlock(T_w_c.inverse(), pose);
  EXPECT_LT((blockToPose(pose).inverse().translation() - T_w_c.translation()).norm(), 1e-12);

  const PinholeCamera cam = syntheticCamera();
  const Eigen::Vector3d p_w = T_w_c * Eigen::Vector3d(0.3, -0.2, 3.0);
  PointTerm<3> pt{K(), cam.projectIdeal(Eigen::Vector3d(0.3, -0.2, 3.0)), 0.5, 3.0, 100.0, 1e-3};
  double r[3];
  ASSERT_TRUE(pt(pose, p_w, r));
  EXPECT_NEAR(Eigen::Vector3d(r[0], r[1], r[2]).norm(), 0.0, 1e-9);
  pt.uv.x() += 2.0;  // 2 px off with sigma 2 -> whitened residual -1
  pt.depth += 0.01;  // 1 cm with sigma 1 cm -> -1
  ASSERT_TRUE(pt(pose, p_w, r));
  EXPECT_NEAR(r[0], -1.0, 1e-9);
  EXPECT_NEAR(r[2], -1.0, 1e-9);

  // Behind the camera: not projectable.
  EXPECT_FALSE(pt(pose, Eigen::Vector3d(T_w_c * Eigen::Vector3d(0, 0, -1)), r));

  // Line: endpoints 3 px either side of the observed line -> residuals +-3 / sigma.
  const Eigen::Vector3d A_c(-0.4, 0.1, 2.5), B_c(0.5, 0.3, 3.5);
  const Eigen::Vector2d a = cam.projectIdeal(A_c), b = cam.projectIdeal(B_c);
  const Eigen::Vector2d n = Eigen::Vector2d(-(b - a).y(), (b - a).x()).normalized();
  LineTerm lt;
  lt.K = K(), lt.inv_sigma = 1.0;
  ASSERT_TRUE(normalisedLine(a + 3.0 * n, b + 3.0 * n, &lt.l));
  double rl[2];
  ASSERT_TRUE(lt(pose, Eigen::Vector3d(T_w_c * A_c), Eigen::Vector3d(T_w_c * B_c), rl));
  EXPECT_NEAR(std::abs(rl[0]), 3.0, 1e-9);
  EXPECT_NEAR(std::abs(rl[1]), 3.0, 1e-9);
}

TEST(OptimCosts, AnalyticResidualsMatchTheReferenceTerms) {
  std::mt19937 rng(30);
  const PinholeCamera cam = syntheticCamera();
  double pose[kPoseSize];
  poseToBlock(perturb(pathPose(1, 4), 0.1, 10.0, rng).inverse(), pose);
  const PointTerm<3> pt{K(), {300, 200}, 0.8, 2.6, 100.0, 1e-3};
  const Eigen::Vector3d p_w(0.2, -0.3, 3.0);
  double r_ref[3], r[3];
  ASSERT_TRUE(pt(pose, p_w, r_ref));
  const PointCost<3> c(pt, nullptr);
  double point[3] = {p_w.x(), p_w.y(), p_w.z()};
  const double* params[2] = {pose, point};
  ASSERT_TRUE(c.Evaluate(params, r, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], r_ref[i], 1e-9);

  LineTerm lt;
  lt.K = K(), lt.inv_sigma = 0.7;
  ASSERT_TRUE(normalisedLine({100, 120}, {500, 300}, &lt.l));
  const Eigen::Vector3d P(-0.5, 0.2, 3.0), Q(0.4, -0.3, 2.2);
  double rl_ref[2], rl[2];
  ASSERT_TRUE(lt(pose, P, Q, rl_ref));
  const LineCost lc(lt, nullptr);
  double line[6] = {P.x(), P.y(), P.z(), Q.x(), Q.y(), Q.z()};
  const double* lparams[2] = {pose, line};
  ASSERT_TRUE(lc.Evaluate(lparams, rl, nullptr));
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(rl[i], rl_ref[i], 1e-9);
}

TEST(OptimCosts, JacobiansMatchNumericDifferences) {
  std::mt19937 rng(31);
  const PinholeCamera cam = syntheticCamera();
  const SE3 T_w_c = perturb(pathPose(1, 4), 0.1, 10.0, rng);
  double pose[kPoseSize];
  poseToBlock(T_w_c.inverse(), pose);
  const PoseLiftManifold lift;

  const Eigen::Vector3d X_c(0.3, -0.25, 2.7);
  double point[3];
  Eigen::Vector3d::Map(point) = T_w_c * X_c;
  for (int n : {2, 3}) {
    const Eigen::Vector2d uv = cam.projectIdeal(X_c) + Eigen::Vector2d(1.5, -2.0);
    if (n == 3) {
      const PointCost<3> c({K(), uv, 0.8, 2.6, 1.0 / 0.01, 1e-3}, nullptr);
      expectJacobiansMatchNumeric(c, {&lift, nullptr}, {pose, point});
    } else {
      const PointCost<2> c({K(), uv, 0.8, 0.0, 0.0, 1e-3}, nullptr);
      expectJacobiansMatchNumeric(c, {&lift, nullptr}, {pose, point});
    }
  }

  double line[6];
  Eigen::Vector3d::Map(line) = T_w_c * Eigen::Vector3d(-0.5, 0.2, 3.0);
  Eigen::Vector3d::Map(line + 3) = T_w_c * Eigen::Vector3d(0.4, -0.3, 2.2);
  LineTerm lt;
  lt.K = K(), lt.inv_sigma = 1.0 / 1.2;
  ASSERT_TRUE(normalisedLine({100, 120}, {500, 300}, &lt.l));
  const LineCost lc(lt, nullptr);
  expectJacobiansMatchNumeric(lc, {&lift, nullptr}, {pose, line});

  // The pose-only batch cost, with observations inside and beyond the Huber threshold (weighted).
  PoseOnlyBatchCost batch(pose, std::sqrt(5.991), std::sqrt(7.815));
  const std::uint8_t on = 1, off = 0;
  const Eigen::Vector2d uv = cam.projectIdeal(X_c);
  batch.addPoint(PointTerm<2>{K(), uv + Eigen::Vector2d(0.5, -0.3), 1.0, 0.0, 0.0, 1e-3}, Eigen::Vector3d(point), &on);
  batch.addPoint(PointTerm<2>{K(), uv + Eigen::Vector2d(9.0, 4.0), 1.0, 0.0, 0.0, 1e-3}, Eigen::Vector3d(point), &on);
  batch.addPoint(PointTerm<3>{K(), uv, 1.2, 2.65, 100.0, 1e-3}, Eigen::Vector3d(point), &on);  // 5 sigma in depth
  batch.addPoint(PointTerm<3>{K(), uv + Eigen::Vector2d(30, 0), 1.2, 2.7, 100.0, 1e-3}, Eigen::Vector3d(point), &off);
  batch.addLine(lt, Eigen::Vector3d(line), Eigen::Vector3d(line + 3), &on);
  ASSERT_EQ(batch.num_residuals(), 2 + 2 + 3 + 3 + 2);
  batch.reweight(true);
  ASSERT_LT(batch.monoWeight(1), 1.0);  // the 9.8 px one is beyond the threshold
  // Its parameter is a Euclidean increment around the base pose; away from zero the SO(3)
  // left Jacobian matters.
  double delta[6] = {0.01, -0.02, 0.015, 0.03, -0.05, 0.02};
  expectJacobiansMatchNumeric(batch, {nullptr}, {delta});
  batch.reweight(false);
  expectJacobiansMatchNumeric(batch, {nullptr}, {delta});
  // At delta = 0 it evaluates at the base pose itself.
  double zero[6] = {0, 0, 0, 0, 0, 0}, r_batch[12], r_line[2];
  const double* bp[1] = {zero};
  ASSERT_TRUE(batch.Evaluate(bp, r_batch, nullptr));
  const double* lp[2] = {pose, line};
  ASSERT_TRUE(lc.Evaluate(lp, r_line, nullptr));
  EXPECT_NEAR(r_batch[10], r_line[0], 1e-12);
  EXPECT_NEAR(r_batch[11], r_line[1], 1e-12);

  // The autodiff pose-graph cost on its quaternion manifold.
  const PoseManifold manifold;
  double pose_i[kPoseSize], pose_j[kPoseSize];
  poseToBlock(T_w_c, pose_i);
  poseToBlock(perturb(T_w_c, 0.3, 20.0, rng), pose_j);
  RelativePoseCost rc{Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX())), Eigen::Vector3d(0.1, 0.2, 0.3),
                      Eigen::Matrix<double, 6, 6>::Identity() * 3.0};
  std::unique_ptr<ceres::CostFunction> rel_cost(RelativePoseCost::create(rc));
  expectJacobiansMatchNumeric(*rel_cost, {&manifold, &manifold}, {pose_i, pose_j});
}

TEST(OptimCosts, NegativeFocalLengthsKeepTheirSign) {
  // A camera with fx or fy < 0 (ICL-NUIM publishes fy = -480): residuals vanish at the
  // truth and the analytic Jacobians still match numeric differences.
  std::mt19937 rng(32);
  const SE3 T_w_c = perturb(pathPose(1, 4), 0.1, 10.0, rng);
  double pose[kPoseSize];
  poseToBlock(T_w_c.inverse(), pose);
  const PoseLiftManifold lift;
  for (const auto& [flip_x, flip_y] : {std::pair{false, true}, std::pair{true, false}, std::pair{true, true}}) {
    PinholeCamera cam = syntheticCamera();
    if (flip_x) cam.fx = -cam.fx, cam.cx = (cam.width - 1) - cam.cx;
    if (flip_y) cam.fy = -cam.fy, cam.cy = (cam.height - 1) - cam.cy;
    SCOPED_TRACE(testing::Message() << "fx " << cam.fx << " fy " << cam.fy);
    const Intrinsics Km{cam.fx, cam.fy, cam.cx, cam.cy};
    const Eigen::Vector3d X_c(0.3, -0.25, 2.7), A_c(-0.5, 0.2, 3.0), B_c(0.4, -0.3, 2.2);
    double point[3], line[6];
    Eigen::Vector3d::Map(point) = T_w_c * X_c;
    Eigen::Vector3d::Map(line) = T_w_c * A_c;
    Eigen::Vector3d::Map(line + 3) = T_w_c * B_c;

    // Zero at the truth, whitened pixels off it.
    const Eigen::Vector2d uv = cam.projectIdeal(X_c);
    PointTerm<3> pt{Km, uv, 0.5, X_c.z(), 100.0, 1e-3};
    double r[3];
    ASSERT_TRUE(pt(pose, Eigen::Vector3d(point), r));
    EXPECT_LT(Eigen::Vector3d(r[0], r[1], r[2]).norm(), 1e-9);
    LineTerm lt;
    lt.K = Km, lt.inv_sigma = 1.0 / 1.2;
    ASSERT_TRUE(normalisedLine(cam.projectIdeal(A_c), cam.projectIdeal(B_c), &lt.l));
    double rl[2];
    ASSERT_TRUE(lt(pose, Eigen::Vector3d(line), Eigen::Vector3d(line + 3), rl));
    EXPECT_LT(std::hypot(rl[0], rl[1]), 1e-9);

    const Eigen::Vector2d off = uv + Eigen::Vector2d(1.5, -2.0);
    const PointCost<3> c3({Km, off, 0.8, 2.6, 1.0 / 0.01, 1e-3}, nullptr);
    expectJacobiansMatchNumeric(c3, {&lift, nullptr}, {pose, point});
    const PointCost<2> c2({Km, off, 0.8, 0.0, 0.0, 1e-3}, nullptr);
    expectJacobiansMatchNumeric(c2, {&lift, nullptr}, {pose, point});
    ASSERT_TRUE(normalisedLine({100, 120}, {500, 300}, &lt.l));
    const LineCost lc(lt, nullptr);
    expectJacobiansMatchNumeric(lc, {&lift, nullptr}, {pose, line});

    PoseOnlyBatchCost batch(pose, std::sqrt(5.991), std::sqrt(7.815));
    const std::uint8_t on = 1;
    batch.addPoint(PointTerm<2>{Km, uv + Eigen::Vector2d(0.5, -0.3), 1.0, 0.0, 0.0, 1e-3}, Eigen::Vector3d(point), &on);
    batch.addPoint(PointTerm<3>{Km, uv, 1.2, 2.65, 100.0, 1e-3}, Eigen::Vector3d(point), &on);
    batch.addLine(lt, Eigen::Vector3d(line), Eigen::Vector3d(line + 3), &on);
    batch.reweight(true);
    double delta[6] = {0.01, -0.02, 0.015, 0.03, -0.05, 0.02};
    expectJacobiansMatchNumeric(batch, {nullptr}, {delta});
  }
}

TEST(OptimCosts, BatchWeightsAreTheHuberDerivative) {
  // IRLS: w^2 = rho'(s) of Ceres' HuberLoss at the reweighting pose, so the gradient of the
  // weighted block there is the Huber cost's gradient; unit weights without robustness.
  const SE3 T_w_c = pathPose(0, 3);
  double pose[kPoseSize];
  poseToBlock(T_w_c.inverse(), pose);
  const PinholeCamera cam = syntheticCamera();
  const Eigen::Vector3d X_c(0.1, 0.2, 2.0), p_w = T_w_c * X_c;
  const double delta = std::sqrt(5.991);
  PoseOnlyBatchCost batch(pose, delta, std::sqrt(7.815));
  const std::vector<double> offsets = {0.5, 2.0, 2.5, 10.0, 100.0};
  for (double off : offsets)
    batch.addPoint(PointTerm<2>{K(), cam.projectIdeal(X_c) + Eigen::Vector2d(off, 0.0), 1.0, 0.0, 0.0, 1e-3}, p_w, nullptr);
  batch.reweight(true);
  const ceres::HuberLoss huber(delta);
  for (size_t k = 0; k < offsets.size(); ++k) {
    double rho[3];
    huber.Evaluate(offsets[k] * offsets[k], rho);
    EXPECT_NEAR(batch.monoWeight(k) * batch.monoWeight(k), rho[1], 1e-9) << offsets[k];
  }
  batch.reweight(false);
  for (size_t k = 0; k < offsets.size(); ++k) EXPECT_EQ(batch.monoWeight(k), 1.0);
}

TEST(OptimCosts, PoseLiftManifoldPlusMinusRoundTrip) {
  std::mt19937 rng(32);
  const PoseLiftManifold m;
  double x[kPoseSize], y[kPoseSize], back[6];
  poseToBlock(perturb(pathPose(2, 5), 0.2, 30.0, rng), x);
  const double delta[6] = {0.05, -0.02, 0.1, 0.2, -0.1, 0.05};
  ASSERT_TRUE(m.Plus(x, delta, y));
  ASSERT_TRUE(m.Minus(y, x, back));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], delta[i], 1e-12) << i;
  // A camera point moves as p_c + rho + phi x p_c to first order.
  const Eigen::Vector3d p_w(0.3, 0.1, 2.0);
  const double small[6] = {1e-7, 0, 0, 0, 2e-7, 0};
  ASSERT_TRUE(m.Plus(x, small, y));
  const Eigen::Vector3d pc = blockToPose(x) * p_w, pc2 = blockToPose(y) * p_w;
  const Eigen::Vector3d expect = pc + Eigen::Vector3d(1e-7, 0, 0) + Eigen::Vector3d(0, 2e-7, 0).cross(pc);
  EXPECT_LT((pc2 - expect).norm(), 1e-12);
}

TEST(OptimCosts, LineGaugeManifoldMovesEndpointsPerpendicularOnly) {
  const Eigen::Vector3d P(0.2, -0.1, 2.0), Q(0.9, 0.4, 2.6);
  const LineGaugeManifold m(Q - P);
  ASSERT_EQ(m.AmbientSize(), 6);
  ASSERT_EQ(m.TangentSize(), 4);
  double x[6], y[6], back[4];
  Eigen::Vector3d::Map(x) = P, Eigen::Vector3d::Map(x + 3) = Q;
  const double delta[4] = {0.01, -0.02, 0.03, 0.005};
  ASSERT_TRUE(m.Plus(x, delta, y));
  const Eigen::Vector3d d = (Q - P).normalized();
  EXPECT_NEAR(d.dot(Eigen::Vector3d(y) - P), 0.0, 1e-15);
  EXPECT_NEAR(d.dot(Eigen::Vector3d(y + 3) - Q), 0.0, 1e-15);
  EXPECT_NEAR((Eigen::Vector3d(y) - P).norm(), std::hypot(0.01, 0.02), 1e-15);  // orthonormal basis
  ASSERT_TRUE(m.Minus(y, x, back));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(back[i], delta[i], 1e-15);

  // The line cost's Jacobian through the manifold, against numeric differences.
  const SE3 T_w_c = pathPose(1, 4);
  double pose[kPoseSize];
  poseToBlock(T_w_c.inverse(), pose);
  LineTerm lc;
  lc.K = K();
  ASSERT_TRUE(normalisedLine({100, 120}, {500, 300}, &lc.l));
  Eigen::Vector3d::Map(x) = T_w_c * P, Eigen::Vector3d::Map(x + 3) = T_w_c * Q;
  const LineGaugeManifold m_w(Eigen::Vector3d(x + 3) - Eigen::Vector3d(x));
  const PoseLiftManifold pm;
  const LineCost cost(lc, nullptr);
  expectJacobiansMatchNumeric(cost, {&pm, &m_w}, {pose, x});
}

TEST(OptimCosts, SwitchedOffCostsAreZero) {
  std::uint8_t active = 0;
  PointTerm<2> term{K(), {1000, 1000}, 1.0, 0.0, 0.0, 1e-3};
  const PointCost<2> pc(term, &active);
  double pose[kPoseSize], point[3] = {0, 0, -5}, r[2] = {7, 7}, J0[14], J1[6];
  std::fill(J0, J0 + 14, 1.0);
  std::fill(J1, J1 + 6, 1.0);
  poseToBlock(SE3(), pose);
  const double* params[2] = {pose, point};
  double* jac[2] = {J0, J1};
  ASSERT_TRUE(pc.Evaluate(params, r, jac));  // even behind the camera: off means off
  EXPECT_EQ(r[0], 0.0);
  EXPECT_EQ(r[1], 0.0);
  for (double v : J0) EXPECT_EQ(v, 0.0);
  for (double v : J1) EXPECT_EQ(v, 0.0);
  active = 1;
  EXPECT_FALSE(pc.Evaluate(params, r, jac));  // on: a point behind the camera is an evaluation failure
}
