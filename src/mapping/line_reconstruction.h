// 3D line segments from one RGB-D frame and a 2D segment.
//
// fitLine3D() is PLY-SLAM's method: sample along the 2D segment, back-project every sample
// with its depth and fit a 3D line robustly, so that a missing or wrong depth at an endpoint
// (typical at depth discontinuities) does not lose or corrupt the line.
// backprojectEndpoints() is the classic method (back-project the two endpoints), kept for
// comparison; LineReconstructionRate measures both as PLY-SLAM's "average reconstruction rate".
//
// Both take the segment in RAW (distorted) colour-image pixels, since depth is registered to
// the raw colour image, and return endpoints in the colour camera frame. Stateless and
// thread-safe.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camera/pinhole_camera.h"

namespace plslam {

struct Segment2D;  // core/map.h

class OptionTable;

/// Why a reconstruction succeeded or failed.
enum class LineFitStatus {
  kOk = 0,
  kSegmentTooShort,        ///< 2D segment shorter than min_segment_px
  kTooFewDepthSamples,     ///< fewer than min_inliers samples with a valid depth
  kTooFewInliers,          ///< the best 3D line explains too few samples
  kDegenerateViewingRay,   ///< the 3D line is nearly parallel to a viewing ray (seen end-on)
  kImplausibleLength,      ///< 3D length outside [min_length_m, max_length_m]
  kEndpointDepthMissing,   ///< (endpoint method) no valid depth in range at an endpoint
  kMidpointDepthMismatch,  ///< (endpoint method) the segment disagrees with the depth at its midpoint
};
const char* toString(LineFitStatus status);

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindLineFitOptions (mapping/line_reconstruction.cpp). `plslam run --print-config` lists them.
struct LineFitOptions {
  // Sampling along the segment (fitLine3D).
  double sample_step_px = 2.5;
  int max_samples = 60;
  double min_segment_px = 10.0;
  // Depth lookup.
  double min_depth_m = 0.1;
  double max_depth_m = 6.0;
  int perp_search_px = 2;
  double surface_jump_tolerances = 2.0;
  // Depth noise model and inlier test: tol(z) = inlier_sigmas * depth_noise_coeff * z^2 + inlier_base_m.
  double depth_noise_coeff = 0.0015;
  double inlier_sigmas = 3.0;
  double inlier_base_m = 0.005;
  // Robust fit.
  double min_inlier_ratio = 0.6;
  int min_inliers = 8;
  int refit_iterations = 2;
  double max_extrapolation = 0.2;
  // Plausibility.
  double min_view_angle_deg = 10.0;
  double min_length_m = 0.02;
  double max_length_m = 10.0;
  // Endpoint method only.
  bool endpoint_median3x3 = true;

  /// Depth-dependent inlier tolerance (metres) at depth z.
  double tolerance(double z) const { return inlier_sigmas * depth_noise_coeff * z * z + inlier_base_m; }
  /// Throws ConfigError naming the field when a value is out of range.
  void validate() const;
};

/// Binds `prefix` + "sample_step_px", "max_samples", ...
void bindLineFitOptions(OptionTable* table, const std::string& prefix, LineFitOptions* options);

/// A reconstructed 3D segment in the camera frame; P_c belongs to the 2D endpoint p, Q_c to q.
struct LineSegment3D {
  Eigen::Vector3d P_c = Eigen::Vector3d::Zero();  ///< endpoint for p, camera frame, metres
  Eigen::Vector3d Q_c = Eigen::Vector3d::Zero();  ///< endpoint for q, camera frame, metres
  int inliers = 0;    ///< depth samples supporting the line (endpoint method: 3, the two endpoints and the midpoint)
  double rms_m = 0;   ///< rms distance of the inliers to the line (endpoint method: midpoint depth residual)

  Eigen::Vector3d direction() const { return (Q_c - P_c).normalized(); }
  double length() const { return (Q_c - P_c).norm(); }
};

/// What happened inside one reconstruction, for statistics and tests.
struct LineFitDiagnostics {
  LineFitStatus status = LineFitStatus::kOk;
  int samples = 0;        ///< samples taken along the segment
  int valid_samples = 0;  ///< samples with a valid depth in range
  int inliers = 0;        ///< inliers of the final line
  double rms_m = 0;       ///< rms distance of the inliers to the final line
};

/// PLY-SLAM line reconstruction by fitting (see LineFitOptions for every step's parameter):
///  1. samples evenly spaced along the UNDISTORTED segment (a 3D line is straight there), each
///     looked up at its raw pixel;
///  2. depth per sample from a +-perp_search_px window perpendicular to the segment: only the
///     NEAR surface counts (the run of window pixels connected to the nearest one without a
///     step > surface_jump_tolerances * tolerance), because an occluding edge belongs to the
///     near surface (the box, not the wall behind it); its inverse depth is interpolated at
///     the segment between the nearest pixels on either side, or extrapolated by an affine
///     least-squares fit when the run lies on one side (a silhouette); the sample's own pixel
///     is back-projected with that depth;
///  3. RANSAC over all pairs of valid samples at least a third of the valid samples apart
///     (exhaustive, so deterministic), inliers within tolerance(z) of the line;
///  4. refit by PCA of the inliers weighted by 1/tolerance(z)^2, re-select inliers, repeat;
///  5. endpoints = points of the fitted line closest to the viewing rays through p and q,
///     clamped to the inliers' extent along the line widened by max_extrapolation on each side.
/// Returns nullopt (reason in diag->status) for a too short segment, too little depth, too few
/// inliers, a line seen end-on or an implausible length. Throws DataError when depth_m is not CV_32FC1.
std::optional<LineSegment3D> fitLine3D(const Eigen::Vector2d& p_raw, const Eigen::Vector2d& q_raw,
                                       const cv::Mat& depth_m, const PinholeCamera& cam,
                                       const LineFitOptions& options, LineFitDiagnostics* diag = nullptr);

/// Each segment fitted to one depth image (fitLine3D with default options): its endpoints in
/// the camera frame, for p and q, NaN where the fit fails or when depth_m is empty (a frame
/// that is not a keyframe of a map, as `plslam eval loops` verifies them). Throws DataError
/// when a non-empty depth_m is not CV_32FC1.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segmentsFittedToDepth(const std::vector<Segment2D>& segments,
                                                                                const cv::Mat& depth_m,
                                                                                const PinholeCamera& cam);

/// The comparison method: back-project both endpoints with the depth at their pixel (3x3
/// median or exact, see endpoint_median3x3). Both depths must be valid and in range, and the
/// depth observed where the 3D midpoint projects must agree with the midpoint's depth within
/// tolerance(z); the same length and viewing-angle checks as fitLine3D apply.
std::optional<LineSegment3D> backprojectEndpoints(const Eigen::Vector2d& p_raw, const Eigen::Vector2d& q_raw,
                                                  const cv::Mat& depth_m, const PinholeCamera& cam,
                                                  const LineFitOptions& options,
                                                  LineFitDiagnostics* diag = nullptr);

/// PLY-SLAM's average reconstruction rate: mean over frames of (3D segments built / 2D segments
/// used); frames that used no segment are skipped. One accumulator per method.
class LineReconstructionRate {
 public:
  /// Adds one frame's counts; throws DataError unless 0 <= built <= used.
  void add(int built, int used);
  /// Mean of the per-frame rates; 0 when no frame counted.
  double average() const { return frames_ > 0 ? sum_rates_ / frames_ : 0.0; }
  /// Frames that counted (used > 0).
  int frames() const { return frames_; }
  long long totalBuilt() const { return built_; }
  long long totalUsed() const { return used_; }

 private:
  double sum_rates_ = 0;
  int frames_ = 0;
  long long built_ = 0, used_ = 0;
};

}  // namespace plslam
