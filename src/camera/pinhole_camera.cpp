#include "camera/pinhole_camera.h"

#include <limits>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {
constexpr double kMinFocalPx = 1e-6;
}  // namespace

bool PinholeCamera::hasDistortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

void PinholeCamera::validate(const std::string& source) const {
  auto fail = [&](const std::string& what) { throw DataError(source + ": " + what); };
  if (width <= 0 || height <= 0 || width > 100000 || height > 100000)
    fail(str("image size ", width, "x", height, " is not a positive size"));
  // Signed: a negative focal length flips that image axis (ICL-NUIM's fy = -480). Zero and
  // tiny values are refused as ViSP does (|px|, |py| >= 1e-6).
  if (!std::isfinite(fx) || !std::isfinite(fy) || !(std::abs(fx) >= kMinFocalPx) || !(std::abs(fy) >= kMinFocalPx))
    fail(str("focal lengths px=", fx, " py=", fy, " must be finite and non-zero (at least ", kMinFocalPx,
             " in magnitude; a negative value flips that image axis)"));
  if (!std::isfinite(cx) || !std::isfinite(cy) || cx < 0 || cy < 0 || cx > width || cy > height)
    fail(str("principal point u0=", cx, " v0=", cy, " lies outside the ", width, "x", height, " image"));
  for (double d : dist)
    if (!std::isfinite(d)) fail("a distortion coefficient is not finite");
  if (!std::isfinite(depth_scale) || depth_scale <= 0) fail(str("depth scale ", depth_scale, " must be positive"));
}

Eigen::Vector2d PinholeCamera::distort(const Eigen::Vector2d& uv_ideal) const {
  if (!hasDistortion()) return uv_ideal;
  const double x = (uv_ideal.x() - cx) / fx, y = (uv_ideal.y() - cy) / fy;
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (dist[0] + r2 * (dist[1] + r2 * dist[4]));
  const double xd = x * radial + 2 * dist[2] * x * y + dist[3] * (r2 + 2 * x * x);
  const double yd = y * radial + dist[2] * (r2 + 2 * y * y) + 2 * dist[3] * x * y;
  return {fx * xd + cx, fy * yd + cy};
}

Eigen::Vector2d PinholeCamera::undistort(const Eigen::Vector2d& uv_raw) const {
  if (!hasDistortion()) return uv_raw;
  const double xd = (uv_raw.x() - cx) / fx, yd = (uv_raw.y() - cy) / fy;
  double x = xd, y = yd;
  // Fixed-point iteration as in OpenCV's undistortPoints; converges for realistic lenses.
  for (int i = 0; i < 20; ++i) {
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (dist[0] + r2 * (dist[1] + r2 * dist[4]));
    const double dx = 2 * dist[2] * x * y + dist[3] * (r2 + 2 * x * x);
    const double dy = dist[2] * (r2 + 2 * y * y) + 2 * dist[3] * x * y;
    x = (xd - dx) / radial;
    y = (yd - dy) / radial;
  }
  return {fx * x + cx, fy * y + cy};
}

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p_c) const { return distort(projectIdeal(p_c)); }

Eigen::Vector3d PinholeCamera::unproject(const Eigen::Vector2d& uv_raw, double depth_m) const {
  return unprojectIdeal(undistort(uv_raw), depth_m);
}

cv::Mat depthToMetres(const cv::Mat& depth_raw, double depth_scale) {
  CV_Assert(depth_raw.type() == CV_16UC1);
  cv::Mat out(depth_raw.size(), CV_32FC1);
  const float inv = static_cast<float>(1.0 / depth_scale);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int y = 0; y < depth_raw.rows; ++y) {
    const uint16_t* in = depth_raw.ptr<uint16_t>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < depth_raw.cols; ++x) o[x] = in[x] == 0 ? nan : in[x] * inv;
  }
  return out;
}

cv::Mat metresToDepth(const cv::Mat& depth_m, double depth_scale) {
  CV_Assert(depth_m.type() == CV_32FC1);
  cv::Mat out(depth_m.size(), CV_16UC1);
  for (int y = 0; y < depth_m.rows; ++y) {
    const float* in = depth_m.ptr<float>(y);
    uint16_t* o = out.ptr<uint16_t>(y);
    for (int x = 0; x < depth_m.cols; ++x) {
      const double v = static_cast<double>(in[x]) * depth_scale;
      o[x] = (std::isfinite(v) && v > 0 && v < 65535.5) ? static_cast<uint16_t>(std::lround(v)) : 0;
    }
  }
  return out;
}

}  // namespace plslam
