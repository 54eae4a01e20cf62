// TagFollower, the tag servo's glue for the live front ends (the ROS node's cmd_vel):
// nothing without a target, commands within the limits towards the tag, a zero command
// while it is not seen, and one zero command that drops the target at the standoff, when
// the tag stays unseen or the frames stop, and on a cancel.
#include <gtest/gtest.h>

#include <cmath>

#include "servo/tag_follower.h"

using namespace plslam;

namespace {

// A Burger-like mounting: the optical frame (z forward, x right, y down) 10 cm ahead of the
// wheel axis, 20 cm up.
SE3 cameraOnBase() {
  Eigen::Matrix3d R;
  R << 0, 0, 1,  //
      -1, 0, 0,  //
      0, -1, 0;
  return SE3(Eigen::Quaterniond(R), Eigen::Vector3d(0.1, 0, 0.2));
}

// The tag `depth` metres ahead of the camera, `right` metres to its right, facing it.
SE3 tagAt(double depth, double right = 0) { return SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(right, 0, depth)); }

bool isZero(const VelocityCommand& c) { return c.v == 0 && c.w == 0; }

}  // namespace

TEST(TagFollower, NoTargetNoCommand) {
  TagFollower follower;
  EXPECT_FALSE(follower.active());
  EXPECT_EQ(follower.tagId(), -1);
  EXPECT_FALSE(follower.update(tagAt(1.2), 0));
  EXPECT_FALSE(follower.update(std::nullopt, 0));
  EXPECT_FALSE(follower.checkFrames(100));
  EXPECT_FALSE(follower.cancel()) << "nothing to stop: the robot is not being driven";
}

TEST(TagFollower, ApproachesTheTagWithinTheBurgerLimits) {
  TagFollower follower;
  follower.setTarget(3, cameraOnBase(), 0);
  EXPECT_EQ(follower.tagId(), 3);
  const std::optional<TagFollowCommand> ahead = follower.update(tagAt(1.2), 0);
  ASSERT_TRUE(ahead);
  EXPECT_EQ(ahead->stop, FollowStop::kNone);
  EXPECT_GT(ahead->command.v, 0) << "far: forward";
  EXPECT_NEAR(ahead->command.w, 0, 1e-6) << "straight ahead: no turn";
  EXPECT_NEAR(ahead->step.depth_error, 0.7, 1e-9);
  // The tag on the camera's left (x < 0): turning left.
  const VelocityCommand left = follower.update(tagAt(1.2, -0.3), 0.1)->command;
  EXPECT_GT(left.w, 0);
  for (const double right : {-0.6, -0.2, 0.2, 0.6})
    for (const double depth : {0.3, 1.0, 3.0}) {
      const VelocityCommand c = follower.update(tagAt(depth, right), 0.2)->command;
      EXPECT_LE(std::abs(c.v), 0.22 + 1e-9) << depth << " " << right;
      EXPECT_LE(std::abs(c.w), 2.84 + 1e-9) << depth << " " << right;
    }
  EXPECT_LT(follower.update(tagAt(0.3), 0.3)->command.v, 0) << "too close: backing off";
}

TEST(TagFollower, StopsOnceAtTheStandoff) {
  TagFollower follower;
  follower.setTarget(0, cameraOnBase(), 0);
  const std::optional<TagFollowCommand> c = follower.update(tagAt(0.5 + 0.005), 0);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->stop, FollowStop::kReached);
  EXPECT_TRUE(c->step.done);
  EXPECT_TRUE(isZero(c->command));
  EXPECT_FALSE(follower.active());
  EXPECT_FALSE(follower.update(tagAt(1.2), 0.1)) << "the target is dropped: nothing more";
}

TEST(TagFollower, TheStandoffIsAnOption) {
  TagFollowerOptions options;
  options.servo.standoff = 0.8;
  TagFollower follower(options);
  follower.setTarget(0, cameraOnBase(), 0);
  EXPECT_EQ(follower.update(tagAt(0.5), 0)->stop, FollowStop::kNone);
  EXPECT_EQ(follower.update(tagAt(0.8), 0.1)->stop, FollowStop::kReached);
}

TEST(TagFollower, UnseenGivesZeroCommandsThenDropsTheTarget) {
  TagFollower follower;  // frame_timeout_s 1
  follower.setTarget(0, cameraOnBase(), 0);
  ASSERT_GT(follower.update(tagAt(1.2), 0)->command.v, 0);
  const std::optional<TagFollowCommand> missed = follower.update(std::nullopt, 0.5);
  ASSERT_TRUE(missed);
  EXPECT_EQ(missed->stop, FollowStop::kNone);
  EXPECT_TRUE(isZero(missed->command)) << "not seen: hold still";
  EXPECT_TRUE(follower.active()) << "a missed detection keeps the target";
  // Seen again within the timeout: the approach goes on, and the timeout restarts.
  EXPECT_GT(follower.update(tagAt(1.2), 0.9)->command.v, 0);
  EXPECT_EQ(follower.update(std::nullopt, 1.8)->stop, FollowStop::kNone);
  const std::optional<TagFollowCommand> lost = follower.update(std::nullopt, 2.0);
  ASSERT_TRUE(lost);
  EXPECT_EQ(lost->stop, FollowStop::kLost);
  EXPECT_TRUE(isZero(lost->command));
  EXPECT_FALSE(follower.active());
  EXPECT_FALSE(follower.update(tagAt(1.2), 2.1)) << "not resumed when the tag comes back";
}

TEST(TagFollower, StopsWhenTheFramesStopOrTheTagStaysUnseen) {
  TagFollower follower;
  follower.setTarget(0, cameraOnBase(), 0);
  EXPECT_FALSE(follower.checkFrames(0.9)) << "no frame yet, within the timeout";
  const std::optional<TagFollowCommand> none = follower.checkFrames(1.1);
  ASSERT_TRUE(none) << "a target set and no frame ever came";
  EXPECT_EQ(none->stop, FollowStop::kNoFrames);
  EXPECT_TRUE(isZero(none->command));
  EXPECT_FALSE(follower.active());
  EXPECT_FALSE(follower.checkFrames(5)) << "once";

  // Frames come, the tag not in them: the timer stops the robot even between frames.
  follower.setTarget(0, cameraOnBase(), 10);
  follower.update(tagAt(1.2), 10);
  follower.update(std::nullopt, 10.8);
  EXPECT_FALSE(follower.checkFrames(10.9));
  const std::optional<TagFollowCommand> unseen = follower.checkFrames(11.1);
  ASSERT_TRUE(unseen);
  EXPECT_EQ(unseen->stop, FollowStop::kLost);
}

TEST(TagFollower, CancelGivesOneZeroCommand) {
  TagFollower follower;
  follower.setTarget(0, cameraOnBase(), 0);
  ASSERT_GT(follower.update(tagAt(1.2), 0)->command.v, 0);
  const std::optional<TagFollowCommand> stop = follower.cancel();
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->stop, FollowStop::kCancelled);
  EXPECT_TRUE(isZero(stop->command));
  EXPECT_FALSE(follower.cancel());
  EXPECT_FALSE(follower.update(tagAt(1.2), 0.1));
}

TEST(TagFollower, ANewTargetReplacesTheOld) {
  TagFollower follower;
  follower.setTarget(1, cameraOnBase(), 0);
  follower.setTarget(2, cameraOnBase(), 0);
  EXPECT_EQ(follower.tagId(), 2);
  EXPECT_GT(follower.update(tagAt(1.2), 0)->command.v, 0);
}
