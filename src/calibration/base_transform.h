// Camera-to-base calibration of a mobile robot (TurtleBot3): a target (one AprilTag, or
// any Target) is fixed at a measured pose T_b_target in the robot's base frame; every
// image gives T_c_target, so T_b_c = T_b_target * inverse(T_c_target), averaged over views.
//
// Frames: base = the robot base (ROS REP 103: x forward, y left, z up); camera = the
// colour camera's optical frame (x right, y down, z forward); target = centre of the
// pattern, x to the right as printed, y down, z into the target (see calibration/target.h).
// A tag on a wall facing the robot, upright, has in the base frame roll -90 deg, pitch 0,
// yaw -90 deg (its z points along the base's +x).
//
// The camera-to-base file (read with loadCameraToBase, e.g. by the servo module) is a
// small YAML document:
//
//   # ...comments...
//   format: plslam_camera_to_base 1
//   parent_frame: base
//   child_frame: camera
//   translation: [tx, ty, tz]            # metres: camera origin in the base frame
//   rotation: [qx, qy, qz, qw]           # unit quaternion of R_b_c
//   rpy_deg: [roll, pitch, yaw]          # the same rotation, R = Rz(yaw) Ry(pitch) Rx(roll)
//   visp_pose_vector: [tx, ty, tz, tux, tuy, tuz]   # ViSP vpPoseVector of bMc (theta-u, radians)
//   views: 12
//   spread_translation_m: 0.0003         # RMS distance of the per-view estimates to the mean
//   spread_rotation_deg: 0.02            # RMS angle of the per-view estimates to the mean
//
// p_base = T_b_c * p_camera. translation + rotation define the transform; rpy_deg and
// visp_pose_vector repeat it for people and for ViSP (vpPoseVector/vpHomogeneousMatrix).
#pragma once

#include <string>
#include <vector>

#include "core/se3.h"

namespace plslam::calib {

/// R = Rz(yaw) * Ry(pitch) * Rx(roll), radians (ROS / URDF fixed-axis roll-pitch-yaw).
Eigen::Matrix3d rotationFromRpy(double roll, double pitch, double yaw);
/// roll, pitch, yaw (radians) of R; pitch in [-pi/2, pi/2].
Eigen::Vector3d rpyFromRotation(const Eigen::Matrix3d& R);
/// Parses "x,y,z,roll,pitch,yaw" (metres, degrees). Throws ConfigError naming `what`.
SE3 parsePoseXyzRpyDeg(const std::string& text, const std::string& what);

/// Rotation average (chordal L2 mean: the projection of the summed rotation matrices onto
/// SO(3)) with the mean translation.
SE3 averagePoses(const std::vector<SE3>& poses);

struct CameraToBase {
  SE3 T_b_c;                    ///< p_base = T_b_c * p_camera
  int views = 0;                ///< views averaged
  double spread_t_m = 0;        ///< RMS distance of the per-view translations to the mean
  double spread_r_deg = 0;      ///< RMS angle of the per-view rotations to the mean
  std::vector<SE3> per_view;    ///< T_b_c of every view
};

/// T_b_c from per-view target poses T_c_target and the target's pose in the base frame.
/// Throws DataError when `T_c_target` is empty.
CameraToBase cameraToBase(const std::vector<SE3>& T_c_target, const SE3& T_b_target);

/// Writes the file described above (atomically); `comment` lines go first as # comments.
void saveCameraToBase(const std::string& path, const CameraToBase& calib, const std::string& comment = "");
/// Reads T_b_c from such a file. Throws IoError naming the file and line when it is
/// missing, malformed or the quaternion is not unit length (tolerance 1e-3).
SE3 loadCameraToBase(const std::string& path);

}  // namespace plslam::calib
