// Pose-only optimisation of one RGB-D frame against fixed map points and 3D lines
// (tracking), with ORB-SLAM-like outlier rounds: optimise, classify every observation by
// its chi2, re-optimise with the outliers switched off.
//
// Stateless: each call builds one Ceres problem (all observations in one residual block, the
// Huber loss as weights refreshed at the start of each round) and reuses it across the rounds.
// Thread safety: optimize() is const and may run concurrently on different problems.
#pragma once

#include <string>
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/se3.h"
#include "optim/measurement.h"

namespace plslam {

class OptionTable;

/// A map point seen in the frame. The world point is held fixed.
struct PointObs {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();                ///< world point, metres
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();                 ///< observed ideal pixel
  int octave = 0;                                               ///< pyramid level (sets sigma)
  double depth = std::numeric_limits<double>::quiet_NaN();      ///< measured depth, metres; NaN = none
};

/// A 3D line (world endpoints P, Q, held fixed) seen as the 2D segment p-q.
struct LineObs {
  Eigen::Vector3d P_w = Eigen::Vector3d::Zero();  ///< world endpoint, metres
  Eigen::Vector3d Q_w = Eigen::Vector3d::Zero();  ///< world endpoint, metres
  Eigen::Vector2d p = Eigen::Vector2d::Zero();    ///< observed segment endpoint, ideal pixels
  Eigen::Vector2d q = Eigen::Vector2d::Zero();    ///< observed segment endpoint, ideal pixels
  int octave = 0;                                 ///< pyramid level (sets sigma)
};

struct PoseOnlyProblem {
  SE3 T_w_c_init;                 ///< initial guess of the camera pose in the world
  std::vector<PointObs> points;   ///< point observations
  std::vector<LineObs> lines;     ///< line observations
};

struct PoseOnlyResult {
  SE3 T_w_c;                        ///< optimised pose (the initial one when not converged)
  std::vector<bool> point_inlier;   ///< per PoseOnlyProblem::points entry
  std::vector<bool> line_inlier;    ///< per PoseOnlyProblem::lines entry
  int inliers = 0;                  ///< inlier points + inlier lines
  double final_cost = 0.0;          ///< 0.5 * sum of the squared whitened residuals (chi2) of the inliers
  bool converged = false;           ///< status == kOk
  OptimStatus status = OptimStatus::kNoObservations;
  int iterations = 0;               ///< solver iterations over all rounds
  double time_ms = 0.0;             ///< wall time of optimize()
};

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindPoseOptimizerOptions (optim/option_keys.cpp). `plslam run --print-config` lists them.
struct PoseOptimizerOptions {
  MeasurementModel model;            ///< noise, chi2 gates, depth use
  int rounds = 4;
  int iterations_per_round = 10;
  int min_inliers = 10;
  bool robust_last_round = false;
  bool normal_cholesky = true;
  int num_threads = 1;
};

/// Binds `prefix` + "rounds", "iterations", ...; the model is bound apart (bindMeasurementModel).
void bindPoseOptimizerOptions(OptionTable* table, const std::string& prefix, PoseOptimizerOptions* options);

class PoseOptimizer {
 public:
  explicit PoseOptimizer(PoseOptimizerOptions options = {});
  /// Never throws on degenerate input: no or unusable observations give a non-kOk status
  /// with the initial pose. Line observations whose 2D segment has (near) zero length, and
  /// observations behind the camera, are outliers.
  PoseOnlyResult optimize(const PinholeCamera& camera, const PoseOnlyProblem& problem) const;
  const PoseOptimizerOptions& options() const { return options_; }

 private:
  PoseOptimizerOptions options_;
};

}  // namespace plslam
