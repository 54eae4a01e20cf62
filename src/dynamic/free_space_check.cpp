#include "dynamic/free_space_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace plslam {

namespace {

// The nearest depth in the square window around raw pixel `uv`, NaN when too few of its pixels
// have one (or the window leaves the image).
double nearestDepthAround(const cv::Mat& depth, const Eigen::Vector2d& uv, const FreeSpaceOptions& options) {
  const int r = options.window_radius_px;
  const int x0 = static_cast<int>(std::lround(uv.x())), y0 = static_cast<int>(std::lround(uv.y()));
  if (x0 - r < 0 || y0 - r < 0 || x0 + r >= depth.cols || y0 + r >= depth.rows) return std::nan("");
  double nearest = std::numeric_limits<double>::infinity();
  int valid = 0;
  for (int y = y0 - r; y <= y0 + r; ++y) {
    const float* row = depth.ptr<float>(y);
    for (int x = x0 - r; x <= x0 + r; ++x)
      if (std::isfinite(row[x]) && row[x] > 0) {
        ++valid;
        nearest = std::min(nearest, static_cast<double>(row[x]));
      }
  }
  const int side = 2 * r + 1;
  return valid >= options.min_valid_fraction * side * side && valid > 0 ? nearest : std::nan("");
}

}  // namespace

std::vector<uint8_t> pointsInEarlierFreeSpace(const std::vector<Eigen::Vector3d>& points_cur, const SE3& T_earlier_cur,
                                              const cv::Mat& earlier_depth_m, const PinholeCamera& camera,
                                              const PointNoiseOptions& noise, const FreeSpaceOptions& options) {
  if (earlier_depth_m.type() != CV_32FC1 || earlier_depth_m.cols != camera.width ||
      earlier_depth_m.rows != camera.height)
    throw DataError("free-space check: the earlier depth image must be CV_32FC1 of the camera's size");
  std::vector<uint8_t> in_free_space(points_cur.size(), 0);
  if (!options.enabled) return in_free_space;
  for (size_t i = 0; i < points_cur.size(); ++i) {
    if (!points_cur[i].allFinite()) continue;
    const Eigen::Vector3d q = T_earlier_cur * points_cur[i];
    if (q.z() <= 0) continue;
    const double seen = nearestDepthAround(earlier_depth_m, camera.project(q), options);
    if (!std::isfinite(seen)) continue;
    const double sigma = std::hypot(noise.depthSigma(q.z()), noise.depthSigma(seen));
    in_free_space[i] = seen - q.z() > std::max(options.min_gap_m, options.sigmas * sigma);
  }
  return in_free_space;
}

}  // namespace plslam
