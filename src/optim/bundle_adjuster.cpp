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
#include <memory>

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

// The result before any optimisation: the input values, every observation flagged.
BundleResult inputResult(const BundleProblem& problem) {
  BundleResult result;
  for (const auto& kf : problem.keyframes) result.T_w_c.push_back(kf.T_w_c);
  for (const auto& p : problem.points) result.points.push_back(p.p_w);
  for (const auto& l : problem.lines) result.lines.emplace_back(l.P_w, l.Q_w);
  result.point_obs_outlier.assign(problem.point_obs.size(), true);
  result.line_obs_outlier.assign(problem.line_obs.size(), true);
  return result;
}

// The Ceres parameter blocks (poses hold T_c_w), the measurement terms and the per-observation
// `active` switches of one adjust() call. Ceres keeps pointers into these buffers: the state
// must stay where it was constructed while the Ceres problem lives.
struct BundleState {
  const BundleProblem& problem;
  const MeasurementModel& model;
  const size_t nk, np, nl, npo, nlo;
  std::vector<std::array<double, kPoseSize>> poses;
  // Points and lines share one buffer, points first: Ceres orders the blocks of an
  // elimination group by address, and separate allocations would make that order (and so
  // the rounding of the result) change from run to run within one process.
  std::vector<double> landmarks;
  // Costs; `active` (stable storage, points then lines) switches outliers off in pass 2.
  std::vector<std::uint8_t> active;
  ObservationTerms terms;

  BundleState(const PinholeCamera& camera, const BundleProblem& p, const MeasurementModel& m)
      : problem(p),
        model(m),
        nk(p.keyframes.size()),
        np(p.points.size()),
        nl(p.lines.size()),
        npo(p.point_obs.size()),
        nlo(p.line_obs.size()),
        poses(nk),
        landmarks(static_cast<size_t>(np) * kPointSize + static_cast<size_t>(nl) * kLineSize),
        active(npo + nlo, 0),
        terms(npo, nlo) {
    for (size_t k = 0; k < nk; ++k) poseToBlock(problem.keyframes[k].T_w_c.inverse(), poses[k].data());
    for (size_t i = 0; i < np; ++i) Eigen::Map<Eigen::Vector3d>(pointBlock(i)) = problem.points[i].p_w;
    for (size_t i = 0; i < nl; ++i) {
      Eigen::Map<Eigen::Vector3d>(lineBlock(i)) = problem.lines[i].P_w;
      Eigen::Map<Eigen::Vector3d>(lineBlock(i) + 3) = problem.lines[i].Q_w;
    }
    const Intrinsics K{camera.fx, camera.fy, camera.cx, camera.cy};
    for (size_t i = 0; i < npo; ++i) {
      const auto& o = problem.point_obs[i];
      terms.setPoint(i, K, model, o.uv, o.octave, o.depth);
    }
    for (size_t i = 0; i < nlo; ++i) {
      const auto& o = problem.line_obs[i];
      terms.setLine(i, K, model, o.p, o.q, o.octave);
    }
  }
  BundleState(const BundleState&) = delete;
  BundleState& operator=(const BundleState&) = delete;

  double* pointBlock(size_t i) { return landmarks.data() + i * kPointSize; }
  double* lineBlock(size_t i) { return landmarks.data() + static_cast<size_t>(np) * kPointSize + i * kLineSize; }

  // Whitened chi2 of one observation at the current values; false when it cannot be projected.
  bool pointChi2(size_t i, double* chi2) {
    const auto& o = problem.point_obs[i];
    double r[3] = {0, 0, 0};
    const double* pose = poses[o.keyframe].data();
    const Eigen::Vector3d p_w(pointBlock(o.point));
    const bool ok = terms.has_depth[i] ? terms.rgbd[i](pose, p_w, r) : terms.mono[i](pose, p_w, r);
    *chi2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    return ok;
  }
  bool lineChi2(size_t i, double* chi2) {
    const auto& o = problem.line_obs[i];
    double r[2] = {0, 0};
    const double* L = lineBlock(o.line);
    const bool ok =
        terms.line_ok[i] && terms.lines[i](poses[o.keyframe].data(), Eigen::Vector3d(L), Eigen::Vector3d(L + 3), r);
    *chi2 = r[0] * r[0] + r[1] * r[1];
    return ok;
  }

  // Flags every observation at the current values; returns the outlier count.
  int classify(BundleResult* result) {
    int outliers = 0;
    for (size_t i = 0; i < npo; ++i) {
      double chi2;
      const bool ok = pointChi2(i, &chi2) && chi2 < (terms.has_depth[i] ? model.chi2_3dof : model.chi2_2dof);
      result->point_obs_outlier[i] = !ok;
      outliers += !ok;
    }
    for (size_t i = 0; i < nlo; ++i) {
      double chi2;
      const bool ok = lineChi2(i, &chi2) && chi2 < model.chi2_2dof;
      result->line_obs_outlier[i] = !ok;
      outliers += !ok;
    }
    return outliers;
  }

  // Pass 2 leaves out what classify() flagged after pass 1.
  void deactivateOutliers(const BundleResult& result) {
    for (size_t i = 0; i < npo; ++i) active[i] = active[i] && !result.point_obs_outlier[i];
    for (size_t i = 0; i < nlo; ++i) active[npo + i] = active[npo + i] && !result.line_obs_outlier[i];
  }

  // The optimised values into the result (poses back to T_w_c).
  void readBack(BundleResult* result) {
    for (size_t k = 0; k < nk; ++k) result->T_w_c[k] = blockToPose(poses[k].data()).inverse();
    for (size_t i = 0; i < np; ++i) result->points[i] = Eigen::Vector3d(pointBlock(i));
    for (size_t i = 0; i < nl; ++i)
      result->lines[i] = {Eigen::Vector3d(lineBlock(i)), Eigen::Vector3d(lineBlock(i) + 3)};
  }
};

// What the usable observations (projectable at the initial values, and a real segment)
// constrain: per landmark a constraint count, per keyframe whether it is observed at all.
struct Usage {
  std::vector<int> point_constraints, line_constraints;
  std::vector<bool> kf_used;
  int usable = 0;
};

// Switches the usable observations on in `s.active` and counts what they constrain.
Usage markUsable(BundleState& s) {
  Usage u;
  u.point_constraints.assign(s.np, 0);
  u.line_constraints.assign(s.nl, 0);
  u.kf_used.assign(s.nk, false);
  for (size_t i = 0; i < s.npo; ++i) {
    double chi2;
    if (!s.pointChi2(i, &chi2)) continue;
    s.active[i] = 1;
    ++u.usable;
    const auto& o = s.problem.point_obs[i];
    u.point_constraints[o.point] += s.terms.has_depth[i] ? 2 : 1;  // one RGB-D observation fixes a point
    u.kf_used[o.keyframe] = true;
  }
  for (size_t i = 0; i < s.nlo; ++i) {
    double chi2;
    if (!s.lineChi2(i, &chi2)) continue;
    s.active[s.npo + i] = 1;
    ++u.usable;
    const auto& o = s.problem.line_obs[i];
    ++u.line_constraints[o.line];
    u.kf_used[o.keyframe] = true;
  }
  return u;
}

// Gauge: the caller's fixed keyframes, plus the first used one when none of those in use is fixed.
std::vector<bool> gaugeFixedKeyframes(const BundleProblem& problem, const std::vector<bool>& kf_used) {
  const size_t nk = problem.keyframes.size();
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
  return kf_fixed;
}

struct FreeBlocks {
  int poses = 0;   ///< free keyframe poses
  int blocks = 0;  ///< free parameter blocks of any kind
};

// Adds the blocks that have usable observations (poses in elimination group 1, landmarks in
// group 0) and holds constant what is fixed or under-constrained; returns what stays free.
FreeBlocks addParameterBlocks(BundleState& s, const Usage& u, const std::vector<bool>& kf_fixed, ceres::Problem* cp,
                              ceres::ParameterBlockOrdering* ordering) {
  FreeBlocks free;
  for (size_t k = 0; k < s.nk; ++k) {
    if (!u.kf_used[k]) continue;
    cp->AddParameterBlock(s.poses[k].data(), kPoseSize, new PoseLiftManifold());
    ordering->AddElementToGroup(s.poses[k].data(), 1);
    if (kf_fixed[k])
      cp->SetParameterBlockConstant(s.poses[k].data());
    else
      ++free.poses, ++free.blocks;
  }
  for (size_t i = 0; i < s.np; ++i) {
    if (u.point_constraints[i] == 0) continue;
    cp->AddParameterBlock(s.pointBlock(i), kPointSize);
    ordering->AddElementToGroup(s.pointBlock(i), 0);
    if (s.problem.points[i].fixed || u.point_constraints[i] < 2)
      cp->SetParameterBlockConstant(s.pointBlock(i));
    else
      ++free.blocks;
  }
  for (size_t i = 0; i < s.nl; ++i) {
    if (u.line_constraints[i] == 0) continue;
    double* L = s.lineBlock(i);
    cp->AddParameterBlock(L, kLineSize);
    ordering->AddElementToGroup(L, 0);
    if (s.problem.lines[i].fixed || u.line_constraints[i] < 2) {
      cp->SetParameterBlockConstant(L);
      continue;
    }
    const Eigen::Vector3d d = s.problem.lines[i].Q_w - s.problem.lines[i].P_w;
    if (!(d.norm() > 1e-9)) {  // a point-like segment has no direction: hold it
      cp->SetParameterBlockConstant(L);
      continue;
    }
    cp->SetManifold(L, new LineGaugeManifold(d));
    ++free.blocks;
  }
  return free;
}

// One robust residual per usable observation, switched by its `active` flag.
void addResiduals(BundleState& s, ceres::LossFunction* huber2, ceres::LossFunction* huber3, ceres::Problem* cp) {
  for (size_t i = 0; i < s.npo; ++i) {
    if (!s.active[i]) continue;
    const auto& o = s.problem.point_obs[i];
    if (s.terms.has_depth[i])
      cp->AddResidualBlock(new PointCost<3>(s.terms.rgbd[i], &s.active[i]), huber3, s.poses[o.keyframe].data(),
                           s.pointBlock(o.point));
    else
      cp->AddResidualBlock(new PointCost<2>(s.terms.mono[i], &s.active[i]), huber2, s.poses[o.keyframe].data(),
                           s.pointBlock(o.point));
  }
  for (size_t i = 0; i < s.nlo; ++i) {
    if (!s.active[s.npo + i]) continue;
    const auto& o = s.problem.line_obs[i];
    cp->AddResidualBlock(new LineCost(s.terms.lines[i], &s.active[s.npo + i]), huber2, s.poses[o.keyframe].data(),
                         s.lineBlock(o.line));
  }
}

ceres::Solver::Options solverOptions(const BundleAdjusterOptions& options, int free_poses,
                                     std::shared_ptr<ceres::ParameterBlockOrdering> ordering) {
  ceres::Solver::Options so;
  using LS = BundleAdjusterOptions::LinearSolver;
  LS ls = options.linear_solver;
  if (ls == LS::kAuto) ls = free_poses <= 40 ? LS::kDenseSchur : LS::kSparseSchur;
  if (ls == LS::kSparseSchur && !ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) &&
      !ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE))
    ls = LS::kDenseSchur;  // this Ceres has no sparse backend
  so.linear_solver_type = ls == LS::kDenseSchur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  so.linear_solver_ordering = std::move(ordering);
  so.num_threads = options.num_threads;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  return so;
}

bool allFinite(const BundleResult& result) {
  bool finite = true;
  for (const auto& T : result.T_w_c) finite = finite && T.translation().allFinite() && T.quaternion().coeffs().allFinite();
  for (const auto& p : result.points) finite = finite && p.allFinite();
  for (const auto& l : result.lines) finite = finite && l.first.allFinite() && l.second.allFinite();
  return finite;
}

// Puts the input values back into the result (after a non-finite solution).
void restoreInput(const BundleProblem& problem, BundleResult* result) {
  result->T_w_c.clear();
  for (const auto& kf : problem.keyframes) result->T_w_c.push_back(kf.T_w_c);
  for (size_t i = 0; i < problem.points.size(); ++i) result->points[i] = problem.points[i].p_w;
  for (size_t i = 0; i < problem.lines.size(); ++i) result->lines[i] = {problem.lines[i].P_w, problem.lines[i].Q_w};
}

}  // namespace

BundleAdjuster::BundleAdjuster(BundleAdjusterOptions options) : options_(std::move(options)) {
  options_.model.validate();
  if (options_.max_iterations < 1 || options_.refine_iterations < 0 || !(options_.max_time_s >= 0.0) ||
      options_.num_threads < 1)
    throw ConfigError(str("bundle adjustment: max_iterations (", options_.max_iterations, ") and num_threads (",
                          options_.num_threads, ") must be >= 1, refine_iterations (", options_.refine_iterations,
                          ") and max_time_s (", options_.max_time_s, ") >= 0"));
}

BundleResult BundleAdjuster::adjust(const PinholeCamera& camera, const BundleProblem& problem) const {
  const auto t0 = Clock::now();
  checkIndices(problem);
  const MeasurementModel& model = options_.model;

  BundleResult result = inputResult(problem);
  auto finish = [&](OptimStatus status) {
    result.status = status;
    result.time_ms = 1e3 * secondsSince(t0);
    return result;
  };
  if (problem.point_obs.size() + problem.line_obs.size() == 0) return finish(OptimStatus::kNoObservations);

  BundleState s(camera, problem, model);
  const Usage use = markUsable(s);
  if (use.usable == 0) {
    result.outliers = s.classify(&result);
    return finish(OptimStatus::kNoValidObservations);
  }
  const std::vector<bool> kf_fixed = gaugeFixedKeyframes(problem, use.kf_used);

  ceres::HuberLoss huber2(std::sqrt(model.chi2_2dof));
  ceres::HuberLoss huber3(std::sqrt(model.chi2_3dof));
  ceres::Problem::Options popts;
  popts.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem cp(popts);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  const FreeBlocks free = addParameterBlocks(s, use, kf_fixed, &cp, ordering.get());
  addResiduals(s, &huber2, &huber3, &cp);
  if (free.blocks == 0) {
    result.outliers = s.classify(&result);
    return finish(OptimStatus::kNothingToOptimise);
  }

  ceres::Solver::Options so = solverOptions(options_, free.poses, ordering);
  auto solve = [&](int iterations, ceres::Solver::Summary* summary) {
    so.max_num_iterations = iterations;
    if (options_.max_time_s > 0.0) so.max_solver_time_in_seconds = std::max(0.0, options_.max_time_s - secondsSince(t0));
    ceres::Solve(so, &cp, summary);
    result.iterations += std::max(0, static_cast<int>(summary->iterations.size()) - 1);
    return summary->termination_type != ceres::FAILURE && std::isfinite(summary->final_cost);
  };

  ceres::Solver::Summary s1;
  if (!solve(options_.max_iterations, &s1)) return finish(OptimStatus::kSolverFailed);
  result.initial_cost = s1.initial_cost;
  result.final_cost = s1.final_cost;
  result.outliers = s.classify(&result);

  const bool time_left = options_.max_time_s <= 0.0 || secondsSince(t0) < options_.max_time_s;
  if (options_.refine_iterations > 0 && result.outliers > 0 && time_left) {
    s.deactivateOutliers(result);
    ceres::Solver::Summary s2;
    if (!solve(options_.refine_iterations, &s2)) return finish(OptimStatus::kSolverFailed);
    result.final_cost = s2.final_cost;
    result.outliers = s.classify(&result);
  }

  s.readBack(&result);
  if (!allFinite(result)) {
    restoreInput(problem, &result);
    return finish(OptimStatus::kSolverFailed);
  }
  return finish(OptimStatus::kOk);
}

}  // namespace plslam
