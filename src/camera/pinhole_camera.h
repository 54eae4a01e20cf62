// The pinhole camera of an RGB-D sensor: intrinsics, Brown-Conrady distortion in OpenCV's
// order (k1 k2 p1 p2 k3) and the depth scale of its depth images. Depth is registered to
// the colour image, so depth is looked up at the raw (distorted) colour pixel.
//
// The tracking stages work in *ideal* pixel coordinates (distortion removed once per
// feature); project()/unproject() go through the distortion.
//
// Signed focal lengths. fx or fy may be negative: u = fx x/z + cx, v = fy y/z + cy is still
// a pinhole camera, one whose image columns (fx < 0) or rows (fy < 0) run against the camera
// frame's x or y axis. ICL-NUIM publishes fy = -480: its images are stored upside down with
// respect to the frame of its ground truth, and with the published sign the poses come out
// in that frame. Every formula here keeps the sign (the normalised coordinates
// ((u - cx) / fx, (v - cy) / fy) are the camera frame's, and the distortion acts on them);
// code that needs a length in pixels uses |fx| and |fy|. Zero, tiny (< 1e-6) and non-finite
// focal lengths are refused.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <string>

namespace plslam {

struct PinholeCamera {
  std::string name;                 ///< short label, e.g. "tum_freiburg1"
  int width = 0;                    ///< image width, pixels
  int height = 0;                   ///< image height, pixels
  double fx = 0, fy = 0;            ///< focal lengths, pixels (ViSP px, py); signed, see above
  double cx = 0, cy = 0;            ///< principal point, pixels (ViSP u0, v0)
  std::array<double, 5> dist{};     ///< k1 k2 p1 p2 k3; all zero for an ideal pinhole
  double depth_scale = 5000.0;      ///< depth image units per metre (TUM: 5000, D435i: 1000)

  bool hasDistortion() const;
  /// Throws DataError naming `source` when a value is out of range (zero, tiny or
  /// non-finite focal length, principal point outside the image, bad size or scale).
  /// Negative focal lengths are valid (see above).
  void validate(const std::string& source) const;

  /// Camera-frame point to raw image pixel (with distortion). z must be > 0.
  Eigen::Vector2d project(const Eigen::Vector3d& p_c) const;
  /// Camera-frame point to ideal (undistorted) pixel.
  Eigen::Vector2d projectIdeal(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  /// Raw pixel and its depth (metres along the optical axis) to a camera-frame point.
  Eigen::Vector3d unproject(const Eigen::Vector2d& uv_raw, double depth_m) const;
  /// Ideal pixel and depth to a camera-frame point.
  Eigen::Vector3d unprojectIdeal(const Eigen::Vector2d& uv_ideal, double depth_m) const {
    return {(uv_ideal.x() - cx) / fx * depth_m, (uv_ideal.y() - cy) / fy * depth_m, depth_m};
  }
  /// Raw pixel to ideal pixel (iterative inversion of the distortion).
  Eigen::Vector2d undistort(const Eigen::Vector2d& uv_raw) const;
  /// Ideal pixel to raw pixel.
  Eigen::Vector2d distort(const Eigen::Vector2d& uv_ideal) const;

  /// Camera-frame direction towards the top of the image: -y, or +y when fy < 0. It points
  /// up when the camera is held level (what the floor of the dense grid starts from).
  Eigen::Vector3d imageUp() const { return {0.0, fy < 0 ? 1.0 : -1.0, 0.0}; }

  bool inImage(const Eigen::Vector2d& uv, double border = 0.0) const {
    return uv.x() >= border && uv.y() >= border && uv.x() <= width - 1 - border && uv.y() <= height - 1 - border;
  }
  cv::Matx33d K() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
  cv::Mat distCoeffs() const { return cv::Mat(1, 5, CV_64F, const_cast<double*>(dist.data())).clone(); }
};

/// Depth in metres at the nearest pixel of a CV_32F metric depth image; NaN when outside
/// the image or invalid.
inline float depthAt(const cv::Mat& depth_m, double u, double v) {
  const int x = static_cast<int>(std::lround(u));
  const int y = static_cast<int>(std::lround(v));
  if (x < 0 || y < 0 || x >= depth_m.cols || y >= depth_m.rows) return std::nanf("");
  return depth_m.at<float>(y, x);
}

/// Converts a raw depth image (CV_16UC1, `depth_scale` units per metre, 0 = no reading)
/// to metres (CV_32FC1, NaN = no reading).
cv::Mat depthToMetres(const cv::Mat& depth_raw, double depth_scale);
/// The inverse, for writing depth PNGs; NaN and out-of-range values become 0.
cv::Mat metresToDepth(const cv::Mat& depth_m, double depth_scale);

}  // namespace plslam
