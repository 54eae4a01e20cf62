#include "dense/keyframe_cloud.h"

#include <cmath>

#include "core/error.h"
#include "core/log.h"
#include "dense/voxel_grid.h"

namespace plslam {

namespace {

void checkImage(const cv::Mat& m, int type, const PinholeCamera& camera, const char* what) {
  if (m.empty()) return;
  if (m.type() != type || m.cols != camera.width || m.rows != camera.height)
    throw DataError(str("makeKeyframeCloud: ", what, " must be ", cv::typeToString(type), " of ", camera.width, "x",
                        camera.height, ", got ", cv::typeToString(m.type()), " of ", m.cols, "x", m.rows));
}

/// A flying pixel (half foreground, half background) differs from a neighbour by much
/// more than the sensor noise; NaN neighbours say nothing.
bool onDepthEdge(const cv::Mat& depth_m, int u, int v, float d, float jump) {
  if (jump <= 0) return false;
  const float limit = jump * d;
  const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int x = u + du[k], y = v + dv[k];
    if (x < 0 || y < 0 || x >= depth_m.cols || y >= depth_m.rows) continue;
    const float n = depth_m.at<float>(y, x);
    if (std::isfinite(n) && std::fabs(n - d) > limit) return true;
  }
  return false;
}

/// Depth noise is independent per pixel: averaging a window of the same surface reduces it
/// by its size. Inverse depth is linear in the pixel coordinates over a plane, so its mean
/// over a symmetric window is the centre's; the gate keeps other surfaces out.
double smoothedDepth(const cv::Mat& depth_m, int u, int v, float d, int radius, double depth_sigma_coeff) {
  if (radius == 0) return static_cast<double>(d);
  const double gate = 3.0 * depth_sigma_coeff * d * d;
  double sum = 0;
  int n = 0;
  for (int y = std::max(0, v - radius); y <= std::min(depth_m.rows - 1, v + radius); ++y) {
    const float* row = depth_m.ptr<float>(y);
    for (int x = std::max(0, u - radius); x <= std::min(depth_m.cols - 1, u + radius); ++x) {
      const float z = row[x];
      if (std::isfinite(z) && std::fabs(z - d) <= gate) sum += 1.0 / z, ++n;
    }
  }
  return n > 0 ? n / sum : static_cast<double>(d);
}

/// One point per voxel of the keyframe grid.
std::vector<DensePoint> voxelDownsample(const std::vector<DensePoint>& raw, double voxel_m) {
  dense_detail::VoxelAccumulator grid(voxel_m);
  for (const DensePoint& p : raw) grid.add(p.p_c, p.r, p.g, p.b, p.class_id);
  std::vector<DensePoint> out;
  out.reserve(grid.size());
  grid.forEach(1, [&](const Eigen::Vector3f& c, uint8_t r, uint8_t g, uint8_t b, int16_t cls, int) {
    DensePoint p;
    p.p_c = c;
    p.r = r;
    p.g = g;
    p.b = b;
    p.class_id = cls;
    out.push_back(p);
  });
  return out;
}

}  // namespace

std::vector<DensePoint> makeKeyframeCloud(const PinholeCamera& camera, const cv::Mat& bgr, const cv::Mat& depth_m,
                                          const cv::Mat& dynamic_mask, const cv::Mat& class_image,
                                          const DenseOptions& o) {
  if (depth_m.empty()) throw DataError("makeKeyframeCloud: no depth image");
  checkImage(depth_m, CV_32FC1, camera, "the depth image");
  checkImage(bgr, CV_8UC3, camera, "the colour image");
  checkImage(dynamic_mask, CV_8UC1, camera, "the dynamic mask");
  checkImage(class_image, CV_16SC1, camera, "the class image");
  const int stride = std::max(1, o.pixel_stride);
  const float jump = static_cast<float>(o.edge_jump_ratio);
  const int radius = std::max(0, o.smooth_radius_px);

  std::vector<DensePoint> raw;
  raw.reserve(static_cast<size_t>(depth_m.rows / stride + 1) * (depth_m.cols / stride + 1));
  for (int v = 0; v < depth_m.rows; v += stride) {
    const float* drow = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; u += stride) {
      const float d = drow[u];
      if (!std::isfinite(d) || d < o.min_depth_m || d > o.max_depth_m) continue;
      if (!dynamic_mask.empty() && dynamic_mask.at<uint8_t>(v, u) == 0) continue;
      if (onDepthEdge(depth_m, u, v, d, jump)) continue;
      DensePoint p;
      p.p_c = camera.unproject(Eigen::Vector2d(u, v), smoothedDepth(depth_m, u, v, d, radius, o.depth_sigma_coeff))
                  .cast<float>();
      if (bgr.empty()) {
        p.r = p.g = p.b = 128;
      } else {
        const cv::Vec3b c = bgr.at<cv::Vec3b>(v, u);
        p.b = c[0];
        p.g = c[1];
        p.r = c[2];
      }
      p.class_id = class_image.empty() ? int16_t{-1} : class_image.at<int16_t>(v, u);
      raw.push_back(p);
    }
  }
  if (o.keyframe_voxel_m <= 0) return raw;
  return voxelDownsample(raw, o.keyframe_voxel_m);
}

}  // namespace plslam
