#include "servo/tag_follower.h"

#include "camera/visp_conversion.h"

namespace plslam {

void TagFollower::setTarget(int tag_id, const SE3& T_base_cam, double now_s) {
  servo_ = std::make_unique<TagServo>(toVisp(T_base_cam), options_.servo);
  tag_id_ = tag_id;
  last_frame_s_ = last_seen_s_ = now_s;
}

std::optional<TagFollowCommand> TagFollower::update(const std::optional<SE3>& T_c_tag, double now_s) {
  if (!servo_) return std::nullopt;
  last_frame_s_ = now_s;
  if (!T_c_tag) {
    if (now_s - last_seen_s_ > options_.frame_timeout_s) return stop(FollowStop::kLost);
    TagFollowCommand out;  // a missed detection: hold still, keep the target
    out.step = servo_->lost();
    return out;
  }
  last_seen_s_ = now_s;
  TagFollowCommand out;
  out.step = servo_->update(toVisp(*T_c_tag));
  out.command = out.step.command;
  if (out.step.done) {
    // At the standoff the robot stops and waits for the next target rather than holding
    // the tag against detection noise.
    servo_.reset();
    out.command = VelocityCommand();
    out.stop = FollowStop::kReached;
  }
  return out;
}

std::optional<TagFollowCommand> TagFollower::checkFrames(double now_s) {
  if (!servo_ || now_s - last_seen_s_ <= options_.frame_timeout_s) return std::nullopt;
  return stop(now_s - last_frame_s_ > options_.frame_timeout_s ? FollowStop::kNoFrames : FollowStop::kLost);
}

std::optional<TagFollowCommand> TagFollower::cancel() { return stop(FollowStop::kCancelled); }

std::optional<TagFollowCommand> TagFollower::stop(FollowStop why) {
  if (!servo_) return std::nullopt;
  servo_.reset();
  TagFollowCommand out;
  out.stop = why;
  return out;
}

}  // namespace plslam
