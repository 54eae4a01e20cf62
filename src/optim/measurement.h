// The measurement model shared by the optimisers: pixel and depth noise, chi2 gates, and
// the outcome of a solve. No Ceres here, so mapping/frontend can include it freely.
//
// All image measurements are in IDEAL (undistorted) pixels of a pinhole camera; only
// fx, fy, cx, cy of PinholeCamera are used, never its distortion.
#pragma once

#include <Eigen/Core>
#include <string>

namespace plslam {

class OptionTable;

/// The depth noise coefficient the SLAM solvers (tracking, local and global BA) use: depth
/// trusted like ORB-SLAM's virtual stereo pixel (sigma_z ~ z^2 / 40). A tighter sigma lets
/// depth noise at corners and the colour/depth time offset drag the pose (docs/RESULTS.md,
/// "Design choices measured earlier"). MeasurementModel's own default is the sensor's noise.
constexpr double kSolverDepthSigmaCoeff = 0.025;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindMeasurementModel (optim/option_keys.cpp). `plslam run --print-config` lists them.
struct MeasurementModel {
  double pixel_sigma = 1.0;
  double scale_factor = 1.2;         ///< pyramid scale between octaves: sigma = pixel_sigma * scale_factor^octave
  double depth_sigma_coeff = 0.0015;
  double chi2_2dof = 5.991;
  double chi2_3dof = 7.815;
  bool use_depth = true;
  double min_depth = 1e-3;

  /// Pixel sigma of a feature at `octave`.
  double pixelSigma(int octave) const;
  /// Depth sigma (metres) of a reading of `z` metres.
  double depthSigma(double z) const { return depth_sigma_coeff * z * z; }
  /// True when `depth` is a usable reading and depth residuals are on.
  bool hasDepth(double depth) const;
  /// Throws ConfigError when a field is out of range.
  void validate() const;
};

/// Binds the model's keys, `prefix` + "pixel_sigma" and so on; `where` ("in pose
/// optimisation") ends their doc lines. scale_factor is left out: the run sets it from
/// features.orb_scale_factor, the pyramid the keypoints come from.
void bindMeasurementModel(OptionTable* table, const std::string& prefix, const std::string& where,
                          MeasurementModel* model);

/// Outcome of an optimisation call. Anything but kOk means the result must not be trusted.
enum class OptimStatus {
  kOk,                  ///< the solver ran and enough inliers remain
  kNoObservations,      ///< the problem has no observation at all
  kNoValidObservations, ///< every observation is unusable (behind the camera, degenerate segment)
  kTooFewInliers,       ///< fewer inliers than the caller's minimum after outlier rejection
  kSolverFailed,        ///< Ceres reported a failure (non-finite cost, bad evaluation)
  kNothingToOptimise,   ///< every parameter is fixed (pose graph / BA)
};
const char* toString(OptimStatus status);

/// Infinite 2D line through ideal pixels p and q, (a, b, c) with a^2 + b^2 = 1, so
/// that a*u + b*v + c is the signed distance of (u, v) to it, in pixels. Returns false
/// (and leaves `l` untouched) when p and q (nearly) coincide.
bool normalisedLine(const Eigen::Vector2d& p, const Eigen::Vector2d& q, Eigen::Vector3d* l);

}  // namespace plslam
