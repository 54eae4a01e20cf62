#include "camera/depth_correction.h"

#include <cmath>

#include "core/error.h"

namespace plslam {

void validateDepthCorrection(const DepthCorrection& c) {
  if (!(std::isfinite(c.scale) && c.scale > 0))
    throw ConfigError("calibration.depth_scale must be positive (measured = scale * true + offset)");
  if (!std::isfinite(c.offset_m)) throw ConfigError("calibration.depth_offset_m must be a finite number (metres)");
}

cv::Mat correctDepth(const cv::Mat& depth_m, const DepthCorrection& c) {
  if (c.identity() || depth_m.empty()) return depth_m;
  if (depth_m.type() != CV_32FC1) throw DataError("correctDepth: depth must be CV_32FC1 metres");
  cv::Mat out;
  // NaN stays NaN through the affine map; zero (no reading in some sources) must stay zero.
  depth_m.convertTo(out, CV_32F, 1.0 / c.scale, -c.offset_m / c.scale);
  out.setTo(0, depth_m == 0);
  return out;
}

}  // namespace plslam
