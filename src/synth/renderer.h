// The CPU ray caster of the synthetic scenes: colour (anti-aliased at edges), exact or
// Kinect-like noisy depth, and per-pixel instance ids of the moving objects.
//
// Depth, instance ids and the noise are taken at pixel centres (the ray through pixel
// (u, v) is K^-1 [u v 1]), so a depth pixel back-projects exactly onto the surface its
// ray hit; colour averages several samples where a pixel straddles an edge.
// A frame is a pure function of (scene, pose, time, noise stream): render() is const,
// thread-safe and gives byte-identical images for the same seed.
//
// Fast scene (Scene::exposureNs() > 0): render() averages the colour of sub-frames rendered
// along the true path over the exposure, centred on the frame stamp, so the blur follows
// the image motion; depth, instance ids and T_w_c are those at the stamp. The colour is
// multiplied by Scene::exposureGain(t) before the colour noise (every kind; 1 but there).
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
  /// Sub-frames averaged over the exposure (1: one instant, no blur): enough for the image
  /// to move at most FastMotionOptions::blur_step_px between them, capped.
  int subframes = 1;
  double gain = 1.0;       ///< exposure gain applied to the colour

  /// As the pipeline's input frame (the images are shared, not copied).
  RgbdFrame toRgbdFrame() const;
};

/// Renders frame `frame_index` (0 <= index < scene.frameCount()) at its pose and time,
/// motion blurred over the exposure when the scene has one.
RenderedFrame render(const Scene& scene, int frame_index);

/// Renders the scene from any pose at one instant (no motion blur); `noise_stream` selects
/// the noise pattern (render() uses the frame index).
RenderedFrame renderView(const Scene& scene, const SE3& T_w_c, TimeNs t_ns, uint64_t noise_stream);

}  // namespace plslam::synth
