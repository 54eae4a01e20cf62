#include "optim/pose_optimizer.h"

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "core/error.h"
#include "core/log.h"

#include "optim/cost_functions.h"
#include "optim/observation_terms.h"

namespace plslam {

using namespace optim_internal;

namespace {

Intrinsics intrinsicsOf(const PinholeCamera& camera) { return {camera.fx, camera.fy, camera.cx, camera.cy}; }

}  // namespace

PoseOptimizer::PoseOptimizer(PoseOptimizerOptions options) : options_(std::move(options)) {
  options_.model.validate();
  if (options_.rounds < 1 || options_.iterations_per_round < 1 || options_.min_inliers < 0 || options_.num_threads < 1)
    throw ConfigError(str("pose optimiser: rounds (", options_.rounds, "), iterations_per_round (",
                          options_.iterations_per_round, ") and num_threads (", options_.num_threads,
                          ") must be >= 1 and min_inliers (", options_.min_inliers, ") >= 0"));
}

PoseOnlyResult PoseOptimizer::optimize(const PinholeCamera& camera, const PoseOnlyProblem& problem) const {
  const auto t0 = std::chrono::steady_clock::now();
  const MeasurementModel& model = options_.model;
  const Intrinsics K = intrinsicsOf(camera);
  const size_t n_points = problem.points.size();
  const size_t n_lines = problem.lines.size();

  PoseOnlyResult result;
  result.T_w_c = problem.T_w_c_init;
  result.point_inlier.assign(n_points, false);
  result.line_inlier.assign(n_lines, false);
  auto finish = [&](OptimStatus status) {
    result.status = status;
    result.converged = status == OptimStatus::kOk;
    if (!result.converged) result.T_w_c = problem.T_w_c_init;
    result.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
  };
  if (n_points + n_lines == 0) return finish(OptimStatus::kNoObservations);

  double pose[kPoseSize];
  poseToBlock(problem.T_w_c_init.inverse(), pose);

  // Per-observation terms; `active` (stable storage, points first, then lines) switches
  // outliers off between rounds.
  std::vector<std::uint8_t> active(n_points + n_lines, 0);
  ObservationTerms terms(n_points, n_lines);
  for (size_t i = 0; i < n_points; ++i) {
    const PointObs& o = problem.points[i];
    terms.setPoint(i, K, model, o.uv, o.octave, o.depth);
  }
  for (size_t i = 0; i < n_lines; ++i) {
    const LineObs& o = problem.lines[i];
    terms.setLine(i, K, model, o.p, o.q, o.octave);
  }
  const auto& mono = terms.mono;
  const auto& rgbd = terms.rgbd;
  const auto& has_depth = terms.has_depth;
  const auto& line_terms = terms.lines;
  const auto& line_ok = terms.line_ok;
  // Whitened chi2 of an observation at the current pose; false when it cannot be projected.
  auto pointChi2 = [&](size_t i, double* chi2) {
    double r[3] = {0, 0, 0};
    const bool ok = has_depth[i] ? rgbd[i](pose, problem.points[i].p_w, r) : mono[i](pose, problem.points[i].p_w, r);
    *chi2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    return ok;
  };
  auto lineChi2 = [&](size_t i, double* chi2) {
    double r[2] = {0, 0};
    const bool ok = line_ok[i] && line_terms[i](pose, problem.lines[i].P_w, problem.lines[i].Q_w, r);
    *chi2 = r[0] * r[0] + r[1] * r[1];
    return ok;
  };

  std::vector<bool> usable(n_points + n_lines, false);

  // Classifies every usable observation at the current pose; returns the inlier count and
  // the (non-robust) cost of the inliers.
  auto classify = [&](double* inlier_cost) {
    int count = 0;
    double cost = 0.0;
    for (size_t i = 0; i < n_points; ++i) {
      double chi2;
      const bool ok = usable[i] && pointChi2(i, &chi2) && chi2 < (has_depth[i] ? model.chi2_3dof : model.chi2_2dof);
      active[i] = ok;
      result.point_inlier[i] = ok;
      if (ok) ++count, cost += 0.5 * chi2;
    }
    for (size_t i = 0; i < n_lines; ++i) {
      double chi2;
      const bool ok = usable[n_points + i] && lineChi2(i, &chi2) && chi2 < model.chi2_2dof;
      active[n_points + i] = ok;
      result.line_inlier[i] = ok;
      if (ok) ++count, cost += 0.5 * chi2;
    }
    if (inlier_cost) *inlier_cost = cost;
    return count;
  };

  // Usable = projectable at the initial pose (a point behind the camera cannot be linearised)
  // and, for lines, a non-degenerate segment. Unusable observations stay outliers.
  int n_usable = 0;
  for (size_t i = 0; i < n_points + n_lines; ++i) {
    double chi2;
    usable[i] = i < n_points ? pointChi2(i, &chi2) : lineChi2(i - n_points, &chi2);
    n_usable += usable[i];
  }
  if (n_usable == 0) return finish(OptimStatus::kNoValidObservations);
  for (size_t i = 0; i < usable.size(); ++i) active[i] = usable[i];

  // One residual block for everything (see PoseOnlyBatchCost); the problem owns it.
  // The parameter is a 6-dof increment around `pose`, folded back after every solve.
  double delta[6] = {0, 0, 0, 0, 0, 0};
  auto* cost = new PoseOnlyBatchCost(pose, std::sqrt(model.chi2_2dof), std::sqrt(model.chi2_3dof));
  for (size_t i = 0; i < n_points; ++i) {
    if (!usable[i]) continue;
    if (has_depth[i])
      cost->addPoint(rgbd[i], problem.points[i].p_w, &active[i]);
    else
      cost->addPoint(mono[i], problem.points[i].p_w, &active[i]);
  }
  for (size_t i = 0; i < n_lines; ++i)
    if (usable[n_points + i])
      cost->addLine(line_terms[i], problem.lines[i].P_w, problem.lines[i].Q_w, &active[n_points + i]);
  ceres::Problem ceres_problem;
  ceres_problem.AddResidualBlock(cost, nullptr, delta);

  ceres::Solver::Options so;
  so.linear_solver_type = options_.normal_cholesky ? ceres::DENSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  so.max_num_iterations = options_.iterations_per_round;
  so.num_threads = options_.num_threads;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;

  const int rounds = options_.rounds;
  int inliers = 0;
  for (int round = 0; round < rounds; ++round) {
    const bool robust = round < rounds - 1 || rounds == 1 || options_.robust_last_round;
    cost->reweight(robust);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &ceres_problem, &summary);
    double moved[kPoseSize];
    PoseLiftManifold::plus(pose, delta, moved);
    std::copy(moved, moved + kPoseSize, pose);
    std::fill(delta, delta + 6, 0.0);
    result.iterations += std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
      return finish(OptimStatus::kSolverFailed);
    inliers = classify(&result.final_cost);
    if (inliers < options_.min_inliers) break;
  }
  result.inliers = inliers;
  const SE3 T_c_w = blockToPose(pose);
  if (!T_c_w.translation().allFinite() || !T_c_w.quaternion().coeffs().allFinite())
    return finish(OptimStatus::kSolverFailed);
  result.T_w_c = T_c_w.inverse();
  return finish(inliers >= options_.min_inliers ? OptimStatus::kOk : OptimStatus::kTooFewInliers);
}

}  // namespace plslam
