// Geometric evidence of motion between two frames (adjacent, or a few apart for more
// baseline): the camera motion is estimated robustly from the feature correspondences with
// depth (RANSAC over minimal 3-point rigid fits with local refits, then a Gauss-Newton polish
// on the inliers), and every correspondence that disagrees with it is flagged as moving.
//
// Residuals are tested against the sensor's noise, not a fixed distance: each 3D point gets a
// covariance from its pixel noise (lateral, grows with z) and a Kinect-like depth noise (along
// the ray, sigma_z = a z^2 + b), so a person walking across the view at 2 m (3 cm/frame)
// stands out although the depth noise alone is 1.2 cm there. The thresholds are then scaled by
// how much cleaner or noisier the data are than that model (a robust estimate, clamped).
//
// Correspondences without depth on one side are checked by reprojection, on neither side by
// their epipolar distance (or, when the camera hardly translates, by rotation transfer).
//
// Majority assumption: hypotheses are ranked by the median of their chi2 values over the depth
// correspondences (LMedS), i.e. the motion that fits the better half of them best. When a
// moving object holds more than half of the depth features, or when it is near and precise
// while the background is far and noisy (its motion then fits the background within noise),
// its motion can win and the background is flagged instead. A motion prior (the tracker's
// motion-model prediction) guards against that: with one, hypotheses that move any depth
// point more than 3 cm from where the prior puts it are discarded, the prior itself is a
// hypothesis, and ranking uses the lower quartile (the background may be a minority). When
// nothing near the prior finds consensus (a wrong prediction), the check is redone without
// it (prior_rejected).
//
// Stateless and thread-safe.
#pragma once

#include <string>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/se3.h"

namespace plslam {

class OptionTable;

/// One feature seen in the previous and the current frame.
struct MotionCorrespondence {
  Eigen::Vector2d uv_prev{0, 0};  ///< ideal (undistorted) pixel in the previous frame
  Eigen::Vector2d uv_cur{0, 0};   ///< ideal pixel in the current frame
  Eigen::Vector3d p_prev{NAN, NAN, NAN};  ///< point in the previous camera frame from depth; NaN: no depth
  Eigen::Vector3d p_cur{NAN, NAN, NAN};   ///< point in the current camera frame from depth; NaN: no depth
  /// Multiplies PointNoiseOptions::pixel_sigma for this feature (e.g. the ORB level's scale factor).
  double pixel_sigma_scale = 1.0;

  bool hasDepthPrev() const { return p_prev.allFinite() && p_prev.z() > 0; }
  bool hasDepthCur() const { return p_cur.allFinite() && p_cur.z() > 0; }
};

/// Noise of a back-projected depth pixel (Kinect-like).
/// Configuration keys: each field's key, doc string and range are where it is bound, in bindNoise
/// (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct PointNoiseOptions {
  double pixel_sigma = 1.0;
  double depth_sigma_quadratic = 0.0025;
  double depth_sigma_constant = 0.002;

  /// Standard deviation (m) of a depth reading of z metres.
  double depthSigma(double z) const { return depth_sigma_quadratic * z * z + depth_sigma_constant; }
};

/// Covariance (camera frame, m^2) of the point back-projected from ideal pixel `uv` at depth z.
Eigen::Matrix3d pointCovariance(const PinholeCamera& camera, const Eigen::Vector2d& uv, double z,
                                const PointNoiseOptions& noise, double pixel_sigma_scale = 1.0);

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindMotionCheckOptions (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct MotionCheckOptions {
  PointNoiseOptions noise;            ///< sensor noise model the residuals are normalised by
  double chi2_3d = 16.27;
  double chi2_2d = 13.82;
  double chi2_1d = 10.83;
  int min_correspondences = 6;
  int min_with_depth = 6;
  int min_inliers = 6;
  double min_inlier_ratio = 0.2;
  int max_iterations = 500;
  int min_iterations = 50;
  double confidence = 0.999;
  uint64_t seed = 42;
  double min_sample_side_m = 0.02;
  double min_sample_sine = 0.1;
  double rank_quantile = 0.5;
  double prior_rank_quantile = 0.25;
  bool adapt_noise_scale = true;
  double min_noise_scale = 0.25;
  double max_noise_scale = 4.0;
  int refine_iterations = 3;
  double prior_max_displacement_m = 0.03;
  bool prior_fallback = true;
  double min_epipolar_baseline_m = 0.01;
  double min_scene_depth_m = 0.4;
};

/// Binds `prefix` + "chi2_3d", ... and the noise model ("pixel_sigma", ...).
void bindMotionCheckOptions(OptionTable* table, const std::string& prefix, MotionCheckOptions* options);

enum class MotionCheckStatus {
  kOk,                     ///< motion estimated, flags valid
  kTooFewCorrespondences,  ///< fewer than min_correspondences in all
  kTooFewWithDepth,        ///< fewer than min_with_depth with depth in both frames
  kDegenerate,             ///< the depth points are (nearly) collinear or coincident: no rigid fit
  kNoConsensus,            ///< no motion reached min_inliers / min_inlier_ratio (or none near the prior)
};
const char* motionCheckStatusName(MotionCheckStatus status);

/// How a correspondence was checked.
enum class MotionEvidence : uint8_t {
  kNone,           ///< not checked (no motion, or bad input)
  kRigid3d,        ///< depth in both frames: 3D residual
  kReprojection,   ///< depth in one frame: reprojection into the other
  kEpipolar,       ///< no depth: distance to the epipolar line
  kRotation,       ///< no depth and hardly any translation: rotation transfer
};

struct MotionCheckResult {
  MotionCheckStatus status = MotionCheckStatus::kTooFewCorrespondences;
  SE3 T_cur_prev;                      ///< camera motion (p_cur = T_cur_prev * p_prev); identity unless kOk
  int with_depth = 0;                  ///< correspondences with depth in both frames
  int inliers = 0;                     ///< of those, consistent with T_cur_prev
  int hypotheses = 0;                  ///< RANSAC hypotheses scored
  double noise_scale = 1.0;            ///< the chi2 thresholds were multiplied by this (see adapt_noise_scale)
  bool prior_used = false;             ///< a motion prior constrained the result
  bool prior_won = false;              ///< the prior itself had the best support
  bool prior_rejected = false;         ///< a prior was given but found no consensus (fallback result, or kNoConsensus)
  std::vector<uint8_t> moving;         ///< per correspondence: 1 = disagrees with the camera motion
  std::vector<MotionEvidence> evidence;  ///< per correspondence: how it was checked
  std::vector<double> residual;        ///< per correspondence: metres (kRigid3d) or pixels; NaN unchecked
  std::vector<double> chi2;            ///< per correspondence: squared Mahalanobis residual (model units); NaN unchecked

  bool ok() const { return status == MotionCheckStatus::kOk; }
  /// Correspondences with a usable check / flagged as moving.
  int checkedCount() const;
  int movingCount() const;
};

/// Estimates T_cur_prev and flags the moving correspondences. `prior`: an expected T_cur_prev
/// (e.g. the constant-velocity prediction) that constrains the hypotheses; see the file comment.
MotionCheckResult checkMotion(const std::vector<MotionCorrespondence>& correspondences, const PinholeCamera& camera,
                              const MotionCheckOptions& options = {}, const std::optional<SE3>& prior = std::nullopt);

/// Flags the correspondences that disagree with a camera motion already estimated (`T_cur_prev`
/// and the `noise_scale` of checkMotion's result), by the same tests; no estimation. `inliers`
/// counts those with depth on both sides that agree.
MotionCheckResult judgeAgainstMotion(const std::vector<MotionCorrespondence>& correspondences,
                                     const PinholeCamera& camera, const MotionCheckOptions& options,
                                     const SE3& T_cur_prev, double noise_scale);

}  // namespace plslam
