// The CPU ray caster of the synthetic scenes: colour (anti-aliased at edges), exact or
// Kinect-like noisy depth, and per-pixel instance ids of the moving objects.
//
// Depth, instance ids and the noise are taken at pixel centres (the ray through pixel
// (u, v) is K^-1 [u v 1]), so a depth pixel back-projects exactly onto the surface its
// ray hit; colour averages several samples where a pixel straddles an edge.
// A frame is a pure function of (scene, pose, time, noise stream): render() is const,
// thread-safe and gives byte-identical images for the same seed.
#pragma once

#include <opencv2/core.hpp>

#include "core/frame.h"
#include "core/se3.h"
#include "synth/scene.h"

namespace plslam::synth {

struct RenderedFrame {
  int index = -1;          ///< frame index in the scene (-1 for renderView)
  TimeNs t_ns = 0;         ///< frame time
  SE3 T_w_c;               ///< ground-truth camera pose
  cv::Mat bgr;             ///< CV_8UC3
  cv::Mat depth_m;         ///< CV_32FC1, metres along the optical axis, NaN where no reading
  cv::Mat instance_ids;    ///< CV_16UC1, 0 = static background, else the moving object's instance id

  /// As the pipeline's input frame (the images are shared, not copied).
  RgbdFrame toRgbdFrame() const;
};

/// Renders frame `frame_index` (0 <= index < scene.frameCount()) at its pose and time.
RenderedFrame render(const Scene& scene, int frame_index);

/// Renders the scene from any pose at any time; `noise_stream` selects the noise pattern
/// (render() uses the frame index).
RenderedFrame renderView(const Scene& scene, const SE3& T_w_c, TimeNs t_ns, uint64_t noise_stream);

}  // namespace plslam::synth
