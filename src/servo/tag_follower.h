// The tag servo (servo/tag_servo.h) on live camera images, for a front end that drives a
// robot (the ROS node's cmd_vel): it holds at most one tag to approach, turns each frame's
// detection of it into a velocity command, and says when the robot must stop. The sibling
// of GoalFollower (servo/goal_follower.h), with the same safety rules:
//  - no target, no command: nothing is sent until a tag is set (off by default);
//  - a frame where the tag is not seen gives a zero command (the last one would go on
//    driving the robot blind) and keeps the target for frame_timeout_s, since a detection
//    misses now and then; not seen for longer, no frame for frame_timeout_s, the standoff
//    reached (TagServoStep::done), a cancel, a reset and the front end's shutdown each give
//    one zero command and drop the target;
//  - commands are within the base's limits (TagServoOptions::limits).
//
// Thread safety: none; the front end serialises the calls.
#pragma once

#include <memory>
#include <optional>

#include "core/se3.h"
#include "servo/goal_follower.h"
#include "servo/tag_servo.h"

namespace plslam {

/// What the front end sends for one frame.
struct TagFollowCommand {
  VelocityCommand command;             ///< zero when stop != kNone or the tag was not seen
  FollowStop stop = FollowStop::kNone; ///< set on the command that ends the approach; kLost: the tag not seen
  TagServoStep step;                   ///< the servo's step (errors); default when not seen
};

struct TagFollowerOptions {
  TagServoOptions servo;        ///< the controller, the standoff and the base's limits
  double frame_timeout_s = 1.0; ///< stop when the tag was not seen (or no frame came) for this long
};

/// Times are seconds on any monotonic clock of the caller's.
class TagFollower {
 public:
  explicit TagFollower(const TagFollowerOptions& options = {}) : options_(options) {}

  /// Starts approaching tag `tag_id` at time `now_s`, replacing any target; `T_base_cam`:
  /// the camera's pose in the base frame.
  void setTarget(int tag_id, const SE3& T_base_cam, double now_s);
  bool active() const { return servo_ != nullptr; }
  /// The tag being approached, -1 when none.
  int tagId() const { return servo_ ? tag_id_ : -1; }

  /// The command for a frame processed at `now_s`: `T_c_tag` is the tag's pose in the camera
  /// frame, none when it was not seen. None when there is nothing to send (no target).
  std::optional<TagFollowCommand> update(const std::optional<SE3>& T_c_tag, double now_s);
  /// To be called periodically: the zero command when approaching and no frame came (or the
  /// tag was not seen) for frame_timeout_s (the target is dropped), else none.
  std::optional<TagFollowCommand> checkFrames(double now_s);
  /// Drops the target (cancel, reset, shutdown, a pose goal): the zero command to send, none
  /// when there was no target (the robot is not being driven).
  std::optional<TagFollowCommand> cancel();

 private:
  std::optional<TagFollowCommand> stop(FollowStop why);

  TagFollowerOptions options_;
  std::unique_ptr<TagServo> servo_;
  int tag_id_ = -1;
  double last_frame_s_ = 0;  // the last frame's time, or the target's before the first frame
  double last_seen_s_ = 0;   // when the tag was last seen, or the target's time before
};

}  // namespace plslam
