// The depth correction that `plslam calib depth` measures (calibration/depth_check.h):
// the sensor reads measured = scale * true + offset, so a depth image is corrected by
// true = (measured - offset) / scale before anything uses it. Keys calibration.depth_scale
// and calibration.depth_offset_m of a run configuration; System::feed applies it, so run,
// live, bench and the ROS node all see corrected depth.
#pragma once

#include <opencv2/core.hpp>

namespace plslam {

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindCalibrationOptions (system/system_options.cpp). `plslam run --print-config` lists them.
struct DepthCorrection {
  double scale = 1.0;
  double offset_m = 0.0;

  bool identity() const { return scale == 1.0 && offset_m == 0.0; }
};

/// Throws ConfigError when scale is not positive and finite or offset not finite.
void validateDepthCorrection(const DepthCorrection& correction);

/// The corrected copy of `depth_m` (CV_32F metres, NaN = no reading stays NaN); `depth_m`
/// itself (not copied) when the correction is the identity.
cv::Mat correctDepth(const cv::Mat& depth_m, const DepthCorrection& correction);

}  // namespace plslam
