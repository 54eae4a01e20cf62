// From plslam's world to a robot's frames, by REP-103/105, for every front end that
// publishes poses to a robot (the ROS node today).
//
// plslam's world `w` is the first camera's optical frame (x right, y down, z forward).
// A robot's `map` has z up. We define map as the pose the robot's base had at the first
// frame: T_map_world = T_base_cam, so
//
//   T_map_cam(t)  = T_base_cam * T_w_c(t)
//   T_map_base(t) = T_base_cam * T_w_c(t) * T_base_cam^-1
//
// map's x is then the base's forward direction at start and its origin the base's origin
// (on the floor for base_footprint). T_base_cam comes from `plslam calib base`
// (calibration/base_transform.h); without it, opticalToBase() below: the camera at the
// base's origin looking along its x (x forward = optical z, y left = -optical x,
// z up = -optical y), which is right for a level camera and puts map's origin at the
// camera, not on the floor.
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
  SE3 T_map_world() const { return T_base_cam_; }
  SE3 T_map_cam(const SE3& T_w_c) const { return T_base_cam_ * T_w_c; }
  SE3 T_map_base(const SE3& T_w_c) const { return T_base_cam_ * T_w_c * T_base_cam_.inverse(); }

 private:
  SE3 T_base_cam_;
};

}  // namespace plslam
