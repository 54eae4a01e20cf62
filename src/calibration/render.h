// Synthetic images of calibration targets seen by a known PinholeCamera (intrinsics and
// Brown distortion) from known board poses: for the tests and for users who want to try
// `plslam calib` without a camera. Rendering traces the ray of every sub-sample of a pixel
// (supersampling: anti-aliased edges) through the distortion to the board plane, so the
// images are exact up to sampling; blur and noise are optional.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "calibration/target.h"
#include "camera/pinhole_camera.h"
#include "core/se3.h"

namespace plslam::calib {

struct RenderOptions {
  int supersampling = 4;     ///< sub-samples per pixel side (anti-aliasing); 1 = none
  double blur_sigma = 0.0;   ///< Gaussian blur applied after rendering, pixels (0: sharp)
  double noise_sigma = 0.0;  ///< Gaussian intensity noise, grey levels (0: none)
  uint32_t seed = 1;         ///< seed of the noise
  double black = 25;         ///< grey level of the printed black
  double white = 230;        ///< grey level of the paper
  double background = 110;   ///< grey level around the board
};

/// Renders `target` seen from T_c_board as a CV_8UC1 image of the camera's size.
cv::Mat renderTarget(const Target& target, const PinholeCamera& camera, const SE3& T_c_board,
                     const RenderOptions& options = {});

struct DepthRenderOptions {
  double scale = 1.0;        ///< measured = scale * true + offset
  double offset = 0.0;       ///< metres
  double noise_sigma = 0.0;  ///< Gaussian depth noise, metres
  uint32_t seed = 1;         ///< seed of the noise
};

/// Depth image (CV_32F metres along the optical axis, NaN where the ray misses) of the
/// board's plane extended to a wall, as a depth sensor with the given scale/offset error
/// registered to this camera would report it.
cv::Mat renderPlaneDepth(const PinholeCamera& camera, const SE3& T_c_board, const DepthRenderOptions& options = {});

struct ViewPoseOptions {
  double min_fill = 0.40;      ///< smallest pattern width as a fraction of the image width
  double max_fill = 0.75;      ///< largest
  double max_tilt_deg = 40.0;  ///< largest tilt about the board's x and y axes
  double max_roll_deg = 25.0;  ///< largest rotation about the viewing direction
  int border_px = 6;           ///< the printed area stays this far inside the image
};

/// `count` varied board poses T_c_board (tilted, rolled, spread over the image) that keep
/// the whole printed target in view: a good calibration set. Deterministic in `seed`.
std::vector<SE3> makeViewPoses(const Target& target, const PinholeCamera& camera, int count, uint32_t seed,
                               const ViewPoseOptions& options = {});

/// True when the whole printed area of `target` at T_c_board projects inside the image
/// (`border` pixels in) and in front of the camera.
bool targetInView(const Target& target, const PinholeCamera& camera, const SE3& T_c_board, double border = 0.0);

}  // namespace plslam::calib
