// From plslam's world to a robot's frames, by REP-103/105, for every front end that
// publishes poses to a robot (the ROS node today).
//
// plslam's world `w` is the first camera's optical frame (x right, y down, z forward).
// The robot's `map` is the map frame of the files (core/map_frame.h, map_frame.yaml): z up
// along the floor normal, origin on the floor below the base (below the camera without a
// camera-to-base transform) at the first keyframe, x its forward direction. One definition,
// so that what a robot sees in TF and what it loads from the files agree:
//
//   T_map_cam(t)  = T_map_world * T_w_c(t)
//   T_map_base(t) = T_map_world * T_w_c(t) * T_base_cam^-1
//
// The floor is only known once there are map points, so a live session fixes T_map_world
// after its first keyframes (LiveSession::mapFrame) and writes every output in it. Until
// then a front end uses provisionalMapFrame(): the base at the first frame,
// T_map_world = T_base_cam, which is the same frame when the mounting is calibrated and the
// base stands level on the floor (and is at the camera, not on the floor, without one).
// T_base_cam comes from `plslam calib base` (calibration/base_transform.h); without it,
// opticalToBase(): the camera at the base's origin looking along its x (x forward =
// optical z, y left = -optical x, z up = -optical y).
#pragma once

#include "core/se3.h"

namespace plslam {

/// The rotation from an optical frame (z forward, x right, y down) to a body frame
/// (x forward, y left, z up), no translation.
SE3 opticalToBase();

class RobotFrames {
 public:
  explicit RobotFrames(const SE3& T_base_cam = opticalToBase()) : T_base_cam_(T_base_cam) {}
  const SE3& T_base_cam() const { return T_base_cam_; }
  /// The map frame before the session has fixed one (see above).
  SE3 provisionalMapFrame() const { return T_base_cam_; }
  SE3 T_map_cam(const SE3& T_map_world, const SE3& T_w_c) const { return T_map_world * T_w_c; }
  SE3 T_map_base(const SE3& T_map_world, const SE3& T_w_c) const { return T_map_world * T_w_c * T_base_cam_.inverse(); }

 private:
  SE3 T_base_cam_;
};

}  // namespace plslam
