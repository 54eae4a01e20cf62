#include "servo/goal_follower.h"

#include "camera/visp_conversion.h"

namespace plslam {

const char* toString(FollowStop stop) {
  switch (stop) {
    case FollowStop::kNone: return "none";
    case FollowStop::kReached: return "reached";
    case FollowStop::kLost: return "lost";
    case FollowStop::kNoFrames: return "no frames";
    case FollowStop::kCancelled: return "cancelled";
  }
  return "?";
}

void GoalFollower::setGoal(const PlanarPose& goal, double now_s) {
  servo_ = std::make_unique<PoseServo>(goal, options_.servo);
  last_frame_s_ = now_s;
}

std::optional<FollowCommand> GoalFollower::update(const std::optional<SE3>& T_map_base, double now_s) {
  if (!servo_) return std::nullopt;
  last_frame_s_ = now_s;
  if (!T_map_base) return stop(FollowStop::kLost);
  FollowCommand out;
  out.step = servo_->update(toVisp(*T_map_base));
  out.command = out.step.command;
  if (out.step.done) {
    // PoseServo would go on holding the goal against pose noise; a robot that was sent to a
    // goal stops there and waits for the next one.
    servo_.reset();
    out.command = VelocityCommand();
    out.stop = FollowStop::kReached;
  }
  return out;
}

std::optional<FollowCommand> GoalFollower::checkFrames(double now_s) {
  if (!servo_ || now_s - last_frame_s_ <= options_.frame_timeout_s) return std::nullopt;
  return stop(FollowStop::kNoFrames);
}

std::optional<FollowCommand> GoalFollower::cancel() { return stop(FollowStop::kCancelled); }

std::optional<FollowCommand> GoalFollower::stop(FollowStop why) {
  if (!servo_) return std::nullopt;
  servo_.reset();
  FollowCommand out;
  out.stop = why;
  return out;
}

PlanarPose GoalFollower::planarGoal(const SE3& T_map_goal) { return PlanarMap::planar(toVisp(T_map_goal)); }

}  // namespace plslam
