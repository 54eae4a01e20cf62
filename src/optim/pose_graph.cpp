#include "optim/pose_graph.h"

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <ceres/types.h>

#include <Eigen/Cholesky>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/log.h"
#include "optim/cost_functions.h"

namespace plslam {

using namespace optim_internal;

Eigen::Matrix<double, 6, 6> PoseGraphProblem::information(double sigma_trans_m, double sigma_rot_rad) {
  if (!(sigma_trans_m > 0.0) || !(sigma_rot_rad > 0.0))
    throw ConfigError(str("pose graph: sigmas must be > 0 (got ", sigma_trans_m, " m, ", sigma_rot_rad, " rad)"));
  Eigen::Matrix<double, 6, 1> d;
  const double wt = 1.0 / (sigma_trans_m * sigma_trans_m), wr = 1.0 / (sigma_rot_rad * sigma_rot_rad);
  d << wt, wt, wt, wr, wr, wr;
  return d.asDiagonal();
}

namespace {

/// Checks every edge and returns the square roots U of their information matrices (info = U^T U).
std::vector<Eigen::Matrix<double, 6, 6>> edgeSqrtInformation(const PoseGraphProblem& problem) {
  const int nv = static_cast<int>(problem.vertices.size());
  std::vector<Eigen::Matrix<double, 6, 6>> sqrt_info(problem.edges.size());
  for (size_t e = 0; e < problem.edges.size(); ++e) {
    const auto& edge = problem.edges[e];
    if (edge.i < 0 || edge.i >= nv || edge.j < 0 || edge.j >= nv || edge.i == edge.j)
      throw DataError(str("pose graph: edge ", e, " links vertices ", edge.i, " and ", edge.j, " (have ", nv, ")"));
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(edge.information);
    if (llt.info() != Eigen::Success || !edge.information.isApprox(edge.information.transpose(), 1e-9))
      throw DataError(str("pose graph: edge ", e, " has an information matrix that is not symmetric positive definite"));
    sqrt_info[e] = llt.matrixU();  // info = U^T U, so |U e|^2 = e^T info e
  }
  return sqrt_info;
}

/// Adds the vertices that have edges, holds the fixed ones (or, with none fixed, the first
/// one for the gauge); returns how many stay free.
int addVertices(const PoseGraphProblem& problem, const std::vector<bool>& used,
                std::vector<std::array<double, kPoseSize>>& poses, ceres::Problem* cp) {
  const int nv = static_cast<int>(problem.vertices.size());
  bool any_fixed = false;
  int free_vertices = 0;
  for (int v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    cp->AddParameterBlock(poses[v].data(), kPoseSize, new PoseManifold());
    if (problem.vertices[v].fixed) {
      cp->SetParameterBlockConstant(poses[v].data());
      any_fixed = true;
    } else {
      ++free_vertices;
    }
  }
  if (!any_fixed)  // gauge: hold the first used vertex
    for (int v = 0; v < nv; ++v)
      if (used[v]) {
        cp->SetParameterBlockConstant(poses[v].data());
        --free_vertices;
        break;
      }
  return free_vertices;
}

ceres::Solver::Options solverOptions(const PoseGraphOptions& options) {
  ceres::Solver::Options so;
  const bool sparse = ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ||
                      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE);
  so.linear_solver_type = sparse ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  if (options.max_time_s > 0.0) so.max_solver_time_in_seconds = options.max_time_s;
  so.num_threads = options.num_threads;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  return so;
}

}  // namespace

PoseGraphOptimizer::PoseGraphOptimizer(PoseGraphOptions options) : options_(std::move(options)) {
  if (!(options_.huber_delta >= 0.0) || !(options_.max_time_s >= 0.0) || options_.max_iterations < 1 ||
      options_.num_threads < 1)
    throw ConfigError(str("pose graph: huber_delta (", options_.huber_delta, ") and max_time_s (", options_.max_time_s,
                          ") must be >= 0, max_iterations (", options_.max_iterations, ") and num_threads (",
                          options_.num_threads, ") >= 1"));
}

PoseGraphResult PoseGraphOptimizer::optimize(const PoseGraphProblem& problem) const {
  const auto t0 = std::chrono::steady_clock::now();
  const int nv = static_cast<int>(problem.vertices.size());
  PoseGraphResult result;
  for (const auto& v : problem.vertices) result.T_w_c.push_back(v.T_w_c);
  auto finish = [&](OptimStatus status) {
    result.status = status;
    result.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
  };

  const std::vector<Eigen::Matrix<double, 6, 6>> sqrt_info = edgeSqrtInformation(problem);
  if (problem.edges.empty()) return finish(OptimStatus::kNoObservations);

  std::vector<std::array<double, kPoseSize>> poses(nv);
  std::vector<bool> used(nv, false);
  for (int v = 0; v < nv; ++v) poseToBlock(problem.vertices[v].T_w_c, poses[v].data());
  for (const auto& edge : problem.edges) used[edge.i] = used[edge.j] = true;

  std::unique_ptr<ceres::LossFunction> loss;
  if (options_.huber_delta > 0.0) loss = std::make_unique<ceres::HuberLoss>(options_.huber_delta);
  ceres::Problem::Options popts;
  popts.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem cp(popts);
  const int free_vertices = addVertices(problem, used, poses, &cp);
  for (size_t e = 0; e < problem.edges.size(); ++e) {
    const auto& edge = problem.edges[e];
    RelativePoseCost cost{edge.T_i_j.quaternion(), edge.T_i_j.translation(), sqrt_info[e]};
    cp.AddResidualBlock(RelativePoseCost::create(cost), loss.get(), poses[edge.i].data(), poses[edge.j].data());
  }
  if (free_vertices == 0) return finish(OptimStatus::kNothingToOptimise);

  const ceres::Solver::Options so = solverOptions(options_);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &cp, &summary);
  result.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
    return finish(OptimStatus::kSolverFailed);

  std::vector<SE3> out(nv);
  for (int v = 0; v < nv; ++v) {
    out[v] = blockToPose(poses[v].data());
    if (!out[v].translation().allFinite() || !out[v].quaternion().coeffs().allFinite())
      return finish(OptimStatus::kSolverFailed);
  }
  result.T_w_c = std::move(out);
  return finish(OptimStatus::kOk);
}

}  // namespace plslam
