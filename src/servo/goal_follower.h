// The pose servo on a live SLAM pose, for a front end that drives a robot (the ROS node's
// cmd_vel today): it holds at most one goal on the floor of the map frame, turns each
// measured base pose into a velocity command, and says when the robot must stop.
//
// Safety rules, in one place so that every front end follows them:
//  - no goal, no command: nothing is sent until a goal is set (off by default);
//  - a frame without a pose (tracking lost), no frame for frame_timeout_s (the camera or
//    the SLAM stalled: the last command would go on driving the robot), the goal reached, a
//    cancel, a reset of the map and the front end's shutdown each give one zero command and
//    drop the goal. A lost
//    goal is not resumed when tracking returns: the robot waits for a new goal, since the
//    map the goal was given in may have been replaced meanwhile;
//  - commands are within the base's limits (PoseServoOptions::limits, TurtleBot3 Burger).
//
// The map frame is REP-105's: z up along the floor normal, so the base pose T_map_base is
// the servo's plane frame pose pMb directly (servo/unicycle.h).
//
// Thread safety: none; the front end serialises the calls.
#pragma once

#include <memory>
#include <optional>

#include "core/se3.h"
#include "servo/pose_servo.h"

namespace plslam {

/// Why the follower stopped the robot.
enum class FollowStop { kNone, kReached, kLost, kNoFrames, kCancelled };
const char* toString(FollowStop stop);

/// What the front end sends for one frame.
struct FollowCommand {
  VelocityCommand command;             ///< zero when stop != kNone
  FollowStop stop = FollowStop::kNone; ///< set on the command that ends the goal
  ServoStep step;                      ///< the servo's step (stage, errors); default when lost or cancelled
};

struct GoalFollowerOptions {
  PoseServoOptions servo;       ///< the controller and the base's limits
  double frame_timeout_s = 1.0; ///< stop when no frame came for this long while driving
};

/// Times are seconds on any monotonic clock of the caller's.
class GoalFollower {
 public:
  explicit GoalFollower(const GoalFollowerOptions& options = {}) : options_(options) {}

  /// Starts driving to `goal` (in the map frame) at time `now_s`, replacing any goal.
  void setGoal(const PlanarPose& goal, double now_s);
  bool active() const { return servo_ != nullptr; }

  /// The command for a frame processed at `now_s`: `T_map_base` is the base pose, none
  /// when the frame was not tracked. None when there is nothing to send (no goal).
  std::optional<FollowCommand> update(const std::optional<SE3>& T_map_base, double now_s);
  /// To be called periodically: the zero command when driving and no frame came for
  /// frame_timeout_s (the goal is dropped), else none.
  std::optional<FollowCommand> checkFrames(double now_s);
  /// Drops the goal (cancel, reset, shutdown): the zero command to send, none when there
  /// was no goal (the robot is not being driven).
  std::optional<FollowCommand> cancel();

  /// The goal as a planar pose of a map-frame pose: position on the floor, heading of its
  /// x axis projected on the floor.
  static PlanarPose planarGoal(const SE3& T_map_goal);

 private:
  std::optional<FollowCommand> stop(FollowStop why);

  GoalFollowerOptions options_;
  std::unique_ptr<PoseServo> servo_;
  double last_frame_s_ = 0;  // the last frame's time, or the goal's before the first frame
};

}  // namespace plslam
