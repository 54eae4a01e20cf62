// The servo's measurements taken from images rendered at the simulated robot's true pose,
// as the robot would take them from its camera (servo/simulation.h runs the loop):
//
//   - SlamPoses: each view (colour and depth) is tracked by the plslam System; the
//     controller gets the estimated camera pose, so its errors are SLAM's own on this very
//     path (not replayed ones). No pose when tracking is lost: the base stops.
//   - DetectedTag: the AprilTag is detected in each view and its pose cMo comes from its
//     four corners and its size. Not found: the base stops (TagServo::lost()).
//
// The floor-plane frame p of the servo is placed in the room (T_room_p) where its goals lie
// inside the room; frame stamps advance by the control period.
#pragma once

#include <memory>
#include <optional>

#include "servo/simulation.h"
#include "servo_sim/tag_pose.h"
#include "servo_sim/tag_room.h"
#include "system/system.h"

namespace plslam {

/// Where the goal servo's plane frame lies in the room: its origin at (-1.2, 0.3), x
/// along the room's x (east), so that the goals of plslam servo's examples (within about
/// 2 m of the start) stay clear of the walls.
SE3 defaultPlaneInRoom();

/// The plane frame placed so that the tag servo's tag, at (x, y) in it, is on the room's
/// east wall at y = -0.8 (clear of the furniture) and faces the plane's -x.
SE3 planeForTagOnEastWall(double tag_x, double tag_y);

/// The options of the SLAM run in the loop: sequential (deterministic), no dense clouds and
/// no loop closure (nothing the controller reads).
SystemOptions servoSlamOptions();

class SlamPoses : public PoseErrorModel {
 public:
  /// room: what the camera sees; T_room_w: the SLAM map w (the camera at the start) in the
  /// room; dt: the control period (the frames' stamps advance by it).
  SlamPoses(const TagRoom& room, const SE3& T_room_w, double dt, const SystemOptions& options = servoSlamOptions());
  ~SlamPoses() override;
  /// Renders the view at the true pose, tracks it, and gives the estimate in w: the
  /// estimate relative to the first tracked frame, placed at that frame's true pose (the
  /// first frame when it initialises, the identity: what a robot starting there measures).
  std::optional<vpHomogeneousMatrix> measure(int step, const vpHomogeneousMatrix& wMc_true) override;

  int framesFed() const { return frames_; }
  int framesLost() const { return lost_; }
  /// Largest distance between the estimated and the true camera position over the run, metres.
  double maxPositionError() const { return max_position_error_; }
  const System& system() const { return *slam_; }

 private:
  const TagRoom& room_;
  SE3 T_room_w_;
  double dt_;
  std::unique_ptr<System> slam_;
  std::optional<SE3> T_w_slam_;  // the SLAM world in w, fixed at the first tracked frame
  int frames_ = 0, lost_ = 0;
  double max_position_error_ = 0;
};

class DetectedTag : public TagSensor {
 public:
  /// room: what the camera sees (with the tag); T_room_p: the plane frame in the room.
  DetectedTag(const TagRoom& room, const SE3& T_room_p);
  std::optional<vpHomogeneousMatrix> observe(int step, const vpHomogeneousMatrix& pMc_true) override;
  int detections() const { return detections_; }
  int misses() const { return misses_; }

 private:
  const TagRoom& room_;
  SE3 T_room_p_;
  TagPoseDetector detector_;
  int detections_ = 0, misses_ = 0;
};

}  // namespace plslam
