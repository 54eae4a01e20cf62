// Depth check against a plane: the board's pose from its colour image (known intrinsics,
// PnP) gives the true depth of every pixel on the board; the depth image registered to
// the colour image gives the measured depth. A robust line fit over all views gives
//   measured = scale * true + offset
// (a perfect sensor: scale 1, offset 0), with the RMS of the residuals.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calibration/target.h"
#include "camera/pinhole_camera.h"
#include "core/se3.h"

namespace plslam::calib {

/// One view: metric depth (CV_32F, NaN = no reading) and the board pose from the colour image.
struct DepthView {
  std::string name;
  cv::Mat depth_m;
  SE3 T_c_board;
};

struct DepthCheckOptions {
  int stride = 2;             ///< use every stride-th pixel in x and y
  double inset = 0.1;         ///< skip this fraction of the printed area at its edges (mixed pixels)
  int min_pixels = 200;       ///< fewest valid pixels for a view to count
  double outlier_sigmas = 4;  ///< residuals beyond this many robust sigmas are dropped (3 passes)
};

struct DepthFit {
  double scale = 1.0;         ///< measured = scale * true + offset
  double offset = 0.0;        ///< metres
  double rms_m = 0.0;         ///< RMS of the inlier residuals, metres
  int pixels = 0;             ///< inlier pixels used
  int views = 0;              ///< views that contributed
  double min_true_m = 0, max_true_m = 0;  ///< range of true depths covered
  std::vector<std::string> view_notes;    ///< per view: name, pixels, mean residual (or why skipped)
  std::vector<std::string> guidance;      ///< what to add, one line each
};

/// Fits scale and offset over the board area of every view. Throws DataError when no view
/// has enough valid depth on the board.
DepthFit fitDepthScaleOffset(const std::vector<DepthView>& views, const PinholeCamera& camera, const Target& target,
                             const DepthCheckOptions& options = {});

}  // namespace plslam::calib
