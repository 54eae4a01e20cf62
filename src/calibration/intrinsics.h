// Intrinsic calibration from the accepted views of a target (OpenCV calibrateCamera with
// the Brown model k1 k2 p1 p2 k3 or a subset), a second pass without the views whose
// reprojection error is far above the others', and guidance on what the view set lacks
// (image coverage, tilt). The result is a PinholeCamera written as a ViSP XML camera file
// (camera/camera_file.h) whose leading comment records the reprojection RMS and the
// number of views used; ViSP's vpXmlParserCamera reads the file as any other.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calibration/detect.h"
#include "calibration/target.h"
#include "camera/pinhole_camera.h"
#include "core/se3.h"

namespace plslam::calib {

/// Which distortion coefficients are estimated (the others are held at zero).
enum class DistortionModel { kNone, kK1, kK1K2, kK1K2P1P2, kK1K2P1P2K3 };
/// "none", "k1", "k1k2", "k1k2p1p2", "k1k2p1p2k3"; throws ConfigError otherwise.
DistortionModel parseDistortionModel(const std::string& text);
const char* distortionModelName(DistortionModel m);

struct IntrinsicsOptions {
  DistortionModel model = DistortionModel::kK1K2P1P2K3;  ///< coefficients to estimate
  int min_views = 5;                 ///< fewest accepted views for a calibration
  double outlier_factor = 3.0;       ///< drop views whose RMS exceeds this times the median...
  double outlier_min_px = 1.0;       ///< ...and this many pixels, then calibrate again
  double depth_scale = 1000.0;       ///< depth units per metre written to the camera file
  std::string camera_name = "calibrated";  ///< <name> in the camera file
};

struct IntrinsicsResult {
  PinholeCamera camera;
  DistortionModel model = DistortionModel::kK1K2P1P2K3;  ///< the coefficients estimated
  double rms_px = 0;                 ///< reprojection RMS over every point of the used views
  int views_used = 0;
  std::vector<ViewResult> views;     ///< the input views, outliers re-marked kHighError
  std::vector<double> view_rms_px;   ///< per view; NaN when not used
  std::vector<SE3> T_c_board;        ///< per view board pose; identity when not used
  std::array<double, 4> std_dev{};   ///< standard deviation of fx fy cx cy, pixels
  double coverage = 0;               ///< fraction of an 8x6 grid of image cells holding a point
  int tilted_views = 0;              ///< used views whose board is tilted more than 15 degrees
  std::vector<std::string> guidance; ///< what to add to the view set, one line each
};

/// Calibrates from `views` (only accepted ones are used). Throws DataError when fewer than
/// options.min_views views are accepted (the message says which reasons rejected the rest).
IntrinsicsResult calibrateIntrinsics(std::vector<ViewResult> views, const cv::Size& image_size,
                                     const IntrinsicsOptions& options = {});

/// Board pose T_c_board from one view's points with a known camera (planar PnP, refined);
/// `rms_px` receives the reprojection RMS when given. Throws DataError with fewer than 4 points.
SE3 estimateBoardPose(const Observation& obs, const PinholeCamera& camera, double* rms_px = nullptr);

/// The comment saveCalibration writes at the top of the camera file.
std::string calibrationComment(const IntrinsicsResult& result, const Target& target);
/// Writes result.camera as a ViSP XML camera file with calibrationComment() (atomically).
void saveCalibration(const std::string& path, const IntrinsicsResult& result, const Target& target);

}  // namespace plslam::calib
