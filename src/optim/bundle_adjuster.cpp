#include "optim/bundle_adjuster.h"

#include <ceres/loss_function.h>
#include <ceres/ordered_groups.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <ceres/types.h>

#include <array>
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

const Logger& logger() {
  static const Logger l("optim");
  return l;
}

void checkIndices(const BundleProblem& p) {
  const int nk = static_cast<int>(p.keyframes.size());
  const int np = static_cast<int>(p.points.size());
  const int nl = static_cast<int>(p.lines.size());
  for (size_t i = 0; i < p.point_obs.size(); ++i) {
    const auto& o = p.point_obs[i];
    if (o.keyframe < 0 || o.keyframe >= nk || o.point < 0 || o.point >= np)
      throw DataError(str("bundle adjustment: point observation ", i, " refers to keyframe ", o.keyframe, " / point ",
                          o.point, " (have ", nk, " keyframes, ", np, " points)"));
  }
  for (size_t i = 0; i < p.line_obs.size(); ++i) {
    const auto& o = p.line_obs[i];
    if (o.keyframe < 0 || o.keyframe >= nk || o.line < 0 || o.line >= nl)
      throw DataError(str("bundle adjustment: line observation ", i, " refers to keyframe ", o.keyframe, " / line ",
                          o.line, " (have ", nk, " keyframes, ", nl, " lines)"));
  }
}

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

LocalBundleAdjuster::LocalBundleAdjuster(BundleAdjusterOptions options) : options_(std::move(options)) {
  options_.model.validate();
  if (options_.max_iterations < 1 || options_.refine_iterations < 0 || !(options_.max_time_s >= 0.0) ||
      options_.num_threads < 1)
    throw ConfigError(str("bundle adjustment: max_iterations (", options_.max_iterations, ") and num_threads (",
                          options_.num_threads, ") must be >= 1, refine_iterations (", options_.refine_iterations,
                          ") and max_time_s (", options_.max_time_s, ") >= 0"));
}

BundleResult LocalBundleAdjuster::adjust(const PinholeCamera& camera, const BundleProblem& problem) const {
  const auto t0 = Clock::now();
  checkIndices(problem);
  const MeasurementModel& model = options_.model;
  const Intrinsics K{camera.fx, camera.fy, camera.cx, camera.cy};
  const size_t nk = problem.keyframes.size(), np = problem.points.size(), nl = problem.lines.size();
  const size_t npo = problem.point_obs.size(), nlo = problem.line_obs.size();

  BundleResult result;
  for (const auto& kf : problem.keyframes) result.T_w_c.push_back(kf.T_w_c);
  for (const auto& p : problem.points) result.points.push_back(p.p_w);
  for (const auto& l : problem.lines) result.lines.emplace_back(l.P_w, l.Q_w);
  result.point_obs_outlier.assign(npo, true);
  result.line_obs_outlier.assign(nlo, true);
  auto finish = [&](OptimStatus status) {
    result.status = status;
    result.time_ms = 1e3 * secondsSince(t0);
    return result;
  };
  if (npo + nlo == 0) return finish(OptimStatus::kNoObservations);

  // Parameter blocks (poses hold T_c_w).
  std::vector<std::array<double, kPoseSize>> poses(nk);
  // Points and lines share one buffer, points first: Ceres orders the blocks of an
  // elimination group by address, and separate allocations would make that order (and so
  // the rounding of the result) change from run to run within one process.
  std::vector<double> landmarks(static_cast<size_t>(np) * kPointSize + static_cast<size_t>(nl) * kLineSize);
  auto pointBlock = [&](size_t i) { return landmarks.data() + i * kPointSize; };
  auto lineBlock = [&](size_t i) { return landmarks.data() + static_cast<size_t>(np) * kPointSize + i * kLineSize; };
  for (size_t k = 0; k < nk; ++k) poseToBlock(problem.keyframes[k].T_w_c.inverse(), poses[k].data());
  for (size_t i = 0; i < np; ++i) Eigen::Map<Eigen::Vector3d>(pointBlock(i)) = problem.points[i].p_w;
  for (size_t i = 0; i < nl; ++i) {
    Eigen::Map<Eigen::Vector3d>(lineBlock(i)) = problem.lines[i].P_w;
    Eigen::Map<Eigen::Vector3d>(lineBlock(i) + 3) = problem.lines[i].Q_w;
  }

  // Costs; `active` (stable storage, points then lines) switches outliers off in pass 2.
  std::vector<std::uint8_t> active(npo + nlo, 0);
  ObservationTerms terms(npo, nlo);
  for (size_t i = 0; i < npo; ++i) {
    const auto& o = problem.point_obs[i];
    terms.setPoint(i, K, model, o.uv, o.octave, o.depth);
  }
  for (size_t i = 0; i < nlo; ++i) {
    const auto& o = problem.line_obs[i];
    terms.setLine(i, K, model, o.p, o.q, o.octave);
  }
  const auto& mono = terms.mono;
  const auto& rgbd = terms.rgbd;
  const auto& has_depth = terms.has_depth;
  const auto& line_terms = terms.lines;
  const auto& line_ok = terms.line_ok;

  // Whitened chi2 of one observation at the current values; false when it cannot be projected.
  auto pointChi2 = [&](size_t i, double* chi2) {
    const auto& o = problem.point_obs[i];
    double r[3] = {0, 0, 0};
    const double* pose = poses[o.keyframe].data();
    const Eigen::Vector3d p_w(pointBlock(o.point));
    const bool ok = has_depth[i] ? rgbd[i](pose, p_w, r) : mono[i](pose, p_w, r);
    *chi2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    return ok;
  };
  auto lineChi2 = [&](size_t i, double* chi2) {
    const auto& o = problem.line_obs[i];
    double r[2] = {0, 0};
    const double* L = lineBlock(o.line);
    const bool ok =
        line_ok[i] && line_terms[i](poses[o.keyframe].data(), Eigen::Vector3d(L), Eigen::Vector3d(L + 3), r);
    *chi2 = r[0] * r[0] + r[1] * r[1];
    return ok;
  };
  // Flags every observation at the current values; returns the outlier count.
  auto classify = [&]() {
    int outliers = 0;
    for (size_t i = 0; i < npo; ++i) {
      double chi2;
      const bool ok = pointChi2(i, &chi2) && chi2 < (has_depth[i] ? model.chi2_3dof : model.chi2_2dof);
      result.point_obs_outlier[i] = !ok;
      outliers += !ok;
    }
    for (size_t i = 0; i < nlo; ++i) {
      double chi2;
      const bool ok = lineChi2(i, &chi2) && chi2 < model.chi2_2dof;
      result.line_obs_outlier[i] = !ok;
      outliers += !ok;
    }
    return outliers;
  };

  // Usable observations: projectable at the initial values (and a real segment).
  std::vector<int> point_constraints(np, 0), line_constraints(nl, 0);
  std::vector<bool> kf_used(nk, false);
  int usable = 0;
  for (size_t i = 0; i < npo; ++i) {
    double chi2;
    if (!pointChi2(i, &chi2)) continue;
    active[i] = 1;
    ++usable;
    const auto& o = problem.point_obs[i];
    point_constraints[o.point] += has_depth[i] ? 2 : 1;  // one RGB-D observation fixes a point
    kf_used[o.keyframe] = true;
  }
  for (size_t i = 0; i < nlo; ++i) {
    double chi2;
    if (!lineChi2(i, &chi2)) continue;
    active[npo + i] = 1;
    ++usable;
    const auto& o = problem.line_obs[i];
    ++line_constraints[o.line];
    kf_used[o.keyframe] = true;
  }
  if (usable == 0) {
    result.outliers = classify();
    return finish(OptimStatus::kNoValidObservations);
  }

  // Gauge: hold the first used keyframe when the caller fixed none of those in use.
  std::vector<bool> kf_fixed(nk, false);
  bool any_fixed = false;
  for (size_t k = 0; k < nk; ++k) {
    kf_fixed[k] = problem.keyframes[k].fixed;
    any_fixed = any_fixed || (kf_used[k] && kf_fixed[k]);
  }
  if (!any_fixed)
    for (size_t k = 0; k < nk; ++k)
      if (kf_used[k]) {
        kf_fixed[k] = true;
        logger().debug(str("bundle adjustment: no keyframe fixed, holding keyframe ", k, " for the gauge"));
        break;
      }

  ceres::HuberLoss huber2(std::sqrt(model.chi2_2dof));
  ceres::HuberLoss huber3(std::sqrt(model.chi2_3dof));
  ceres::Problem::Options popts;
  popts.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem cp(popts);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int free_poses = 0, free_blocks = 0;
  for (size_t k = 0; k < nk; ++k) {
    if (!kf_used[k]) continue;
    cp.AddParameterBlock(poses[k].data(), kPoseSize, new PoseLiftManifold());
    ordering->AddElementToGroup(poses[k].data(), 1);
    if (kf_fixed[k])
      cp.SetParameterBlockConstant(poses[k].data());
    else
      ++free_poses, ++free_blocks;
  }
  for (size_t i = 0; i < np; ++i) {
    if (point_constraints[i] == 0) continue;
    cp.AddParameterBlock(pointBlock(i), kPointSize);
    ordering->AddElementToGroup(pointBlock(i), 0);
    if (problem.points[i].fixed || point_constraints[i] < 2)
      cp.SetParameterBlockConstant(pointBlock(i));
    else
      ++free_blocks;
  }
  for (size_t i = 0; i < nl; ++i) {
    if (line_constraints[i] == 0) continue;
    double* L = lineBlock(i);
    cp.AddParameterBlock(L, kLineSize);
    ordering->AddElementToGroup(L, 0);
    if (problem.lines[i].fixed || line_constraints[i] < 2) {
      cp.SetParameterBlockConstant(L);
      continue;
    }
    const Eigen::Vector3d d = problem.lines[i].Q_w - problem.lines[i].P_w;
    if (!(d.norm() > 1e-9)) {  // a point-like segment has no direction: hold it
      cp.SetParameterBlockConstant(L);
      continue;
    }
    cp.SetManifold(L, new LineGaugeManifold(d));
    ++free_blocks;
  }
  for (size_t i = 0; i < npo; ++i) {
    if (!active[i]) continue;
    const auto& o = problem.point_obs[i];
    if (has_depth[i])
      cp.AddResidualBlock(new PointCost<3>(rgbd[i], &active[i]), &huber3, poses[o.keyframe].data(),
                          pointBlock(o.point));
    else
      cp.AddResidualBlock(new PointCost<2>(mono[i], &active[i]), &huber2, poses[o.keyframe].data(),
                          pointBlock(o.point));
  }
  for (size_t i = 0; i < nlo; ++i) {
    if (!active[npo + i]) continue;
    const auto& o = problem.line_obs[i];
    cp.AddResidualBlock(new LineCost(line_terms[i], &active[npo + i]), &huber2, poses[o.keyframe].data(),
                        lineBlock(o.line));
  }
  if (free_blocks == 0) {
    result.outliers = classify();
    return finish(OptimStatus::kNothingToOptimise);
  }

  ceres::Solver::Options so;
  using LS = BundleAdjusterOptions::LinearSolver;
  LS ls = options_.linear_solver;
  if (ls == LS::kAuto) ls = free_poses <= 40 ? LS::kDenseSchur : LS::kSparseSchur;
  if (ls == LS::kSparseSchur && !ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) &&
      !ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE))
    ls = LS::kDenseSchur;  // this Ceres has no sparse backend
  so.linear_solver_type = ls == LS::kDenseSchur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  so.linear_solver_ordering = ordering;
  so.num_threads = options_.num_threads;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;

  auto solve = [&](int iterations, ceres::Solver::Summary* summary) {
    so.max_num_iterations = iterations;
    if (options_.max_time_s > 0.0) so.max_solver_time_in_seconds = std::max(0.0, options_.max_time_s - secondsSince(t0));
    ceres::Solve(so, &cp, summary);
    result.iterations += std::max(0, static_cast<int>(summary->iterations.size()) - 1);
    return summary->termination_type != ceres::FAILURE && std::isfinite(summary->final_cost);
  };
  auto restoreInput = [&]() {
    result.T_w_c.clear();
    for (const auto& kf : problem.keyframes) result.T_w_c.push_back(kf.T_w_c);
    for (size_t i = 0; i < np; ++i) result.points[i] = problem.points[i].p_w;
    for (size_t i = 0; i < nl; ++i) result.lines[i] = {problem.lines[i].P_w, problem.lines[i].Q_w};
  };

  ceres::Solver::Summary s1;
  if (!solve(options_.max_iterations, &s1)) return finish(OptimStatus::kSolverFailed);
  result.initial_cost = s1.initial_cost;
  result.final_cost = s1.final_cost;
  result.outliers = classify();

  const bool time_left = options_.max_time_s <= 0.0 || secondsSince(t0) < options_.max_time_s;
  if (options_.refine_iterations > 0 && result.outliers > 0 && time_left) {
    for (size_t i = 0; i < npo; ++i) active[i] = active[i] && !result.point_obs_outlier[i];
    for (size_t i = 0; i < nlo; ++i) active[npo + i] = active[npo + i] && !result.line_obs_outlier[i];
    ceres::Solver::Summary s2;
    if (!solve(options_.refine_iterations, &s2)) return finish(OptimStatus::kSolverFailed);
    result.final_cost = s2.final_cost;
    result.outliers = classify();
  }

  for (size_t k = 0; k < nk; ++k) result.T_w_c[k] = blockToPose(poses[k].data()).inverse();
  for (size_t i = 0; i < np; ++i) result.points[i] = Eigen::Vector3d(pointBlock(i));
  for (size_t i = 0; i < nl; ++i) result.lines[i] = {Eigen::Vector3d(lineBlock(i)), Eigen::Vector3d(lineBlock(i) + 3)};
  bool finite = true;
  for (const auto& T : result.T_w_c) finite = finite && T.translation().allFinite() && T.quaternion().coeffs().allFinite();
  for (const auto& p : result.points) finite = finite && p.allFinite();
  for (const auto& l : result.lines) finite = finite && l.first.allFinite() && l.second.allFinite();
  if (!finite) {
    restoreInput();
    return finish(OptimStatus::kSolverFailed);
  }
  return finish(OptimStatus::kOk);
}

}  // namespace plslam
