// Bundle adjustment (local and global) of keyframe poses, map points and 3D line segments.
//
// A 3D line is its two world endpoints (P, Q); each observation is a 2D segment whose
// residual is the pixel distance of the projections of P and Q to the observed infinite
// line. The endpoints could slide along the line without changing any residual (a gauge
// freedom); each free line is therefore updated on a 4-dof manifold where every endpoint
// moves only within the plane through its initial position perpendicular to the initial
// direction. No prior is added; endpoint extents are the caller's (the mapper's) business.
//
// Robustness: a Huber loss per observation (threshold sqrt(chi2): 2 dof for points without
// depth and for lines, 3 dof for points with depth, jointly over pixel and depth). Pass 1
// optimises all usable observations; observations over their chi2 gate are then switched off
// for pass 2; the returned flags are the chi2 test at the final values (for culling).
// Observations that cannot be projected at the initial values (behind the camera) or with a
// zero-length segment are left out and flagged.
//
// Gauge: keyframes flagged fixed are held constant; when none is, the first keyframe that
// has observations is held fixed (with depth this fixes the gauge; without depth the scale
// needs two fixed keyframes). Under-constrained landmarks (a point seen once without depth,
// a line seen fewer than twice) are held constant.
//
// Stateless; thread safety: adjust() is const and may run concurrently on different problems.
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

struct BundleProblem {
  struct Keyframe {
    SE3 T_w_c;           ///< initial pose, camera in world
    bool fixed = false;  ///< held constant (gauge, or outside the local window)
  };
  struct Point {
    Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  ///< initial world position, metres
    bool fixed = false;                             ///< held constant
  };
  struct Line {
    Eigen::Vector3d P_w = Eigen::Vector3d::Zero();  ///< initial world endpoint, metres
    Eigen::Vector3d Q_w = Eigen::Vector3d::Zero();  ///< initial world endpoint, metres
    bool fixed = false;                             ///< held constant
  };
  struct PointObs {
    int keyframe = -1;                                         ///< index into keyframes
    int point = -1;                                            ///< index into points
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();              ///< observed ideal pixel
    int octave = 0;                                            ///< pyramid level (sets sigma)
    double depth = std::numeric_limits<double>::quiet_NaN();   ///< measured depth, metres; NaN = none
  };
  struct LineObs {
    int keyframe = -1;                             ///< index into keyframes
    int line = -1;                                 ///< index into lines
    Eigen::Vector2d p = Eigen::Vector2d::Zero();   ///< observed segment endpoint, ideal pixels
    Eigen::Vector2d q = Eigen::Vector2d::Zero();   ///< observed segment endpoint, ideal pixels
    int octave = 0;                                ///< pyramid level (sets sigma)
  };

  std::vector<Keyframe> keyframes;
  std::vector<Point> points;
  std::vector<Line> lines;
  std::vector<PointObs> point_obs;
  std::vector<LineObs> line_obs;
};

struct BundleResult {
  std::vector<SE3> T_w_c;                                           ///< per keyframe
  std::vector<Eigen::Vector3d> points;                              ///< per point
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;   ///< per line: (P_w, Q_w)
  std::vector<bool> point_obs_outlier;  ///< per point observation: chi2 over the gate or behind the camera
  std::vector<bool> line_obs_outlier;   ///< per line observation: chi2 over the gate, behind, or degenerate
  int outliers = 0;                     ///< point + line observations flagged
  double initial_cost = 0.0;            ///< Ceres cost (robustified) before the first pass
  double final_cost = 0.0;              ///< Ceres cost (robustified) after the last pass
  int iterations = 0;                   ///< solver iterations over both passes
  double time_ms = 0.0;                 ///< wall time of adjust()
  OptimStatus status = OptimStatus::kNoObservations;
  bool ok() const { return status == OptimStatus::kOk; }
};

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindBundleAdjusterOptions (optim/option_keys.cpp). `plslam run --print-config` lists them.
struct BundleAdjusterOptions {
  enum class LinearSolver { kAuto, kDenseSchur, kSparseSchur };
  MeasurementModel model;                 ///< noise, chi2 gates (Huber threshold = sqrt(chi2)), depth use
  int max_iterations = 10;
  int refine_iterations = 10;
  double max_time_s = 0.0;
  LinearSolver linear_solver = LinearSolver::kAuto;
  int num_threads = 1;
};

/// Binds `prefix` + "iterations", "refine_iterations", ...; the model is bound apart (bindMeasurementModel).
void bindBundleAdjusterOptions(OptionTable* table, const std::string& prefix, BundleAdjusterOptions* options);

/// Bundle adjustment of the keyframes and landmarks a problem holds: the local BA of the
/// mapper (a window of free keyframes, the rest fixed) and the loop closer's global BA alike.
class BundleAdjuster {
 public:
  explicit BundleAdjuster(BundleAdjusterOptions options = {});
  /// Throws DataError when an observation refers to a keyframe or landmark out of range.
  /// Degenerate input (no observations, none usable) returns a non-kOk status and the input values.
  BundleResult adjust(const PinholeCamera& camera, const BundleProblem& problem) const;
  const BundleAdjusterOptions& options() const { return options_; }

 private:
  BundleAdjusterOptions options_;
};

}  // namespace plslam
