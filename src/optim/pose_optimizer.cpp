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

// The pose block (T_c_w), the per-observation terms and the `active` switches (stable storage,
// points first, then lines) that turn outliers off between rounds. The batch cost keeps
// pointers into this state: it must stay where it was constructed while the problem lives.
struct PoseState {
  const PoseOnlyProblem& problem;
  const MeasurementModel& model;
  const size_t n_points, n_lines;
  double pose[kPoseSize];
  std::vector<std::uint8_t> active;
  ObservationTerms terms;
  std::vector<bool> usable;

  PoseState(const PinholeCamera& camera, const PoseOnlyProblem& p, const MeasurementModel& m)
      : problem(p),
        model(m),
        n_points(p.points.size()),
        n_lines(p.lines.size()),
        active(n_points + n_lines, 0),
        terms(n_points, n_lines),
        usable(n_points + n_lines, false) {
    const Intrinsics K = intrinsicsOf(camera);
    poseToBlock(problem.T_w_c_init.inverse(), pose);
    for (size_t i = 0; i < n_points; ++i) {
      const PointObs& o = problem.points[i];
      terms.setPoint(i, K, model, o.uv, o.octave, o.depth);
    }
    for (size_t i = 0; i < n_lines; ++i) {
      const LineObs& o = problem.lines[i];
      terms.setLine(i, K, model, o.p, o.q, o.octave);
    }
  }
  PoseState(const PoseState&) = delete;
  PoseState& operator=(const PoseState&) = delete;

  // Whitened chi2 of an observation at the current pose; false when it cannot be projected.
  bool pointChi2(size_t i, double* chi2) const {
    double r[3] = {0, 0, 0};
    const bool ok = terms.has_depth[i] ? terms.rgbd[i](pose, problem.points[i].p_w, r)
                                       : terms.mono[i](pose, problem.points[i].p_w, r);
    *chi2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    return ok;
  }
  bool lineChi2(size_t i, double* chi2) const {
    double r[2] = {0, 0};
    const bool ok = terms.line_ok[i] && terms.lines[i](pose, problem.lines[i].P_w, problem.lines[i].Q_w, r);
    *chi2 = r[0] * r[0] + r[1] * r[1];
    return ok;
  }

  // Usable = projectable at the initial pose (a point behind the camera cannot be linearised)
  // and, for lines, a non-degenerate segment. Unusable observations stay outliers. Switches
  // the usable ones on; returns their count.
  int markUsable() {
    int n_usable = 0;
    for (size_t i = 0; i < n_points + n_lines; ++i) {
      double chi2;
      usable[i] = i < n_points ? pointChi2(i, &chi2) : lineChi2(i - n_points, &chi2);
      n_usable += usable[i];
    }
    if (n_usable == 0) return 0;
    for (size_t i = 0; i < usable.size(); ++i) active[i] = usable[i];
    return n_usable;
  }

  // Classifies every usable observation at the current pose; returns the inlier count and
  // the (non-robust) cost of the inliers.
  int classify(PoseOnlyResult* result, double* inlier_cost) {
    int count = 0;
    double cost = 0.0;
    for (size_t i = 0; i < n_points; ++i) {
      double chi2;
      const bool ok =
          usable[i] && pointChi2(i, &chi2) && chi2 < (terms.has_depth[i] ? model.chi2_3dof : model.chi2_2dof);
      active[i] = ok;
      result->point_inlier[i] = ok;
      if (ok) ++count, cost += 0.5 * chi2;
    }
    for (size_t i = 0; i < n_lines; ++i) {
      double chi2;
      const bool ok = usable[n_points + i] && lineChi2(i, &chi2) && chi2 < model.chi2_2dof;
      active[n_points + i] = ok;
      result->line_inlier[i] = ok;
      if (ok) ++count, cost += 0.5 * chi2;
    }
    if (inlier_cost) *inlier_cost = cost;
    return count;
  }

  // One residual block for everything (see PoseOnlyBatchCost); the caller's problem takes it.
  PoseOnlyBatchCost* makeBatchCost() {
    auto* cost = new PoseOnlyBatchCost(pose, std::sqrt(model.chi2_2dof), std::sqrt(model.chi2_3dof));
    for (size_t i = 0; i < n_points; ++i) {
      if (!usable[i]) continue;
      if (terms.has_depth[i])
        cost->addPoint(terms.rgbd[i], problem.points[i].p_w, &active[i]);
      else
        cost->addPoint(terms.mono[i], problem.points[i].p_w, &active[i]);
    }
    for (size_t i = 0; i < n_lines; ++i)
      if (usable[n_points + i])
        cost->addLine(terms.lines[i], problem.lines[i].P_w, problem.lines[i].Q_w, &active[n_points + i]);
    return cost;
  }

  // Folds a solved increment into `pose` and zeroes it for the next round.
  void applyIncrement(double* delta) {
    double moved[kPoseSize];
    PoseLiftManifold::plus(pose, delta, moved);
    std::copy(moved, moved + kPoseSize, pose);
    std::fill(delta, delta + 6, 0.0);
  }
};

ceres::Solver::Options solverOptions(const PoseOptimizerOptions& options) {
  ceres::Solver::Options so;
  so.linear_solver_type = options.normal_cholesky ? ceres::DENSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  so.max_num_iterations = options.iterations_per_round;
  so.num_threads = options.num_threads;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  return so;
}

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
  PoseOnlyResult result;
  result.T_w_c = problem.T_w_c_init;
  result.point_inlier.assign(problem.points.size(), false);
  result.line_inlier.assign(problem.lines.size(), false);
  auto finish = [&](OptimStatus status) {
    result.status = status;
    result.converged = status == OptimStatus::kOk;
    if (!result.converged) result.T_w_c = problem.T_w_c_init;
    result.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
  };
  if (problem.points.size() + problem.lines.size() == 0) return finish(OptimStatus::kNoObservations);

  PoseState s(camera, problem, options_.model);
  if (s.markUsable() == 0) return finish(OptimStatus::kNoValidObservations);

  // The parameter is a 6-dof increment around `s.pose`, folded back after every solve.
  double delta[6] = {0, 0, 0, 0, 0, 0};
  PoseOnlyBatchCost* cost = s.makeBatchCost();
  ceres::Problem ceres_problem;
  ceres_problem.AddResidualBlock(cost, nullptr, delta);
  const ceres::Solver::Options so = solverOptions(options_);

  const int rounds = options_.rounds;
  int inliers = 0;
  for (int round = 0; round < rounds; ++round) {
    const bool robust = round < rounds - 1 || rounds == 1 || options_.robust_last_round;
    cost->reweight(robust);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &ceres_problem, &summary);
    s.applyIncrement(delta);
    result.iterations += std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
      return finish(OptimStatus::kSolverFailed);
    inliers = s.classify(&result, &result.final_cost);
    if (inliers < options_.min_inliers) break;
  }
  result.inliers = inliers;
  const SE3 T_c_w = blockToPose(s.pose);
  if (!T_c_w.translation().allFinite() || !T_c_w.quaternion().coeffs().allFinite())
    return finish(OptimStatus::kSolverFailed);
  result.T_w_c = T_c_w.inverse();
  return finish(inliers >= options_.min_inliers ? OptimStatus::kOk : OptimStatus::kTooFewInliers);
}

}  // namespace plslam
