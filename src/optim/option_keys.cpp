// The configuration keys of the solvers' options, bound under the prefix of the module that
// runs them (tracker., mapper., loop.): one line per field, with the range a value must be in.
#include <stdexcept>

#include "core/option_table.h"
#include "optim/bundle_adjuster.h"
#include "optim/pose_graph.h"
#include "optim/pose_optimizer.h"

namespace plslam {

void bindMeasurementModel(OptionTable* t, const std::string& p, const std::string& where, MeasurementModel* m) {
  t->bind(p + "pixel_sigma", &m->pixel_sigma, "keypoint and segment sigma at pyramid level 0 " + where + " (px)", above(0));
  t->bind(p + "chi2_2dof", &m->chi2_2dof, "chi-square gate and Huber threshold squared, points without depth and lines " + where, above(0));
  t->bind(p + "chi2_3dof", &m->chi2_3dof, "chi-square gate and Huber threshold squared, points with depth " + where, above(0));
  t->bind(p + "use_depth", &m->use_depth, "depth residuals " + where);
  t->bind(p + "depth_sigma_coeff", &m->depth_sigma_coeff, "depth sigma = coeff * z^2 " + where + " (1/m)", above(0));
  t->bind(p + "min_projection_depth_m", &m->min_depth, "points nearer the image plane than this are not projected " + where + " (m)", above(0));
}

void bindPoseOptimizerOptions(OptionTable* t, const std::string& p, PoseOptimizerOptions* o) {
  t->bind(p + "rounds", &o->rounds, "pose optimisation outlier rounds", atLeast(1));
  t->bind(p + "iterations", &o->iterations_per_round, "solver iterations per round", atLeast(1));
  t->bind(p + "min_inliers", &o->min_inliers, "fewer inlier observations: the solve fails", atLeast(1));
  t->bind(p + "robust_last_round", &o->robust_last_round, "keep the Huber kernel in the last round (ORB-SLAM drops it)");
  t->bind(p + "normal_cholesky", &o->normal_cholesky, "dense normal Cholesky (else dense QR) for the 6-unknown solve (Cholesky is the fastest for one 6-dof block)");
  t->bind(p + "threads", &o->num_threads, "Ceres threads of the pose solve", atLeast(1));
}

void bindBundleAdjusterOptions(OptionTable* t, const std::string& p, BundleAdjusterOptions* o) {
  using Solver = BundleAdjusterOptions::LinearSolver;
  t->bind(p + "iterations", &o->max_iterations, "bundle adjustment iterations (robust pass)", atLeast(1));
  t->bind(p + "refine_iterations", &o->refine_iterations, "bundle adjustment iterations without the outliers (0: none)", atLeast(0));
  t->bind(p + "max_time_s", &o->max_time_s, "bundle adjustment wall-time budget over both passes, seconds (0: none)", atLeast(0));
  t->bindCustom(
      p + "linear_solver", fieldSpan(&o->linear_solver),
      [o](const std::string& v) {
        if (v == "auto") o->linear_solver = Solver::kAuto;
        else if (v == "dense_schur") o->linear_solver = Solver::kDenseSchur;
        else if (v == "sparse_schur") o->linear_solver = Solver::kSparseSchur;
        else throw std::invalid_argument("expected auto, dense_schur or sparse_schur");
      },
      [o] {
        return std::string(o->linear_solver == Solver::kAuto ? "auto"
                           : o->linear_solver == Solver::kDenseSchur ? "dense_schur" : "sparse_schur");
      },
      "auto, dense_schur or sparse_schur", "bundle adjustment linear solver (auto: dense Schur up to 40 free keyframes, else sparse Schur)");
  t->bind(p + "threads", &o->num_threads, "Ceres threads of the bundle adjustment", atLeast(1));
}

void bindPoseGraphOptions(OptionTable* t, const std::string& p, PoseGraphOptions* o) {
  t->bind(p + "iterations", &o->max_iterations, "pose-graph solver iterations", atLeast(1));
  t->bind(p + "max_time_s", &o->max_time_s, "pose-graph time budget, seconds (0: none)", atLeast(0));
  t->bind(p + "huber_delta", &o->huber_delta, "Huber threshold on the whitened edge error (0: plain least squares)", atLeast(0));
  t->bind(p + "threads", &o->num_threads, "Ceres threads of the pose graph", atLeast(1));
}

}  // namespace plslam
