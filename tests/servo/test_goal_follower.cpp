// GoalFollower, the servo glue of the live front ends (the ROS node's cmd_vel): nothing
// without a goal, commands within the limits towards the goal, and one zero command that
// drops the goal when it is reached, when tracking is lost, when the frames stop and on a
// cancel.
#include <gtest/gtest.h>

#include <cmath>

#include "servo/goal_follower.h"

using namespace plslam;

namespace {

SE3 basePose(double x, double y, double yaw) {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())), Eigen::Vector3d(x, y, 0));
}

// The base after `command` for dt seconds (exact unicycle motion for a constant command).
PlanarPose drive(const PlanarPose& p, const VelocityCommand& c, double dt) {
  PlanarPose next = p;
  next.yaw = p.yaw + c.w * dt;
  if (std::abs(c.w) < 1e-9) {
    next.x += c.v * dt * std::cos(p.yaw);
    next.y += c.v * dt * std::sin(p.yaw);
  } else {
    next.x += c.v / c.w * (std::sin(next.yaw) - std::sin(p.yaw));
    next.y -= c.v / c.w * (std::cos(next.yaw) - std::cos(p.yaw));
  }
  return next;
}

bool isZero(const VelocityCommand& c) { return c.v == 0 && c.w == 0; }

}  // namespace

TEST(GoalFollower, NoGoalNoCommand) {
  GoalFollower follower;
  EXPECT_FALSE(follower.active());
  EXPECT_FALSE(follower.update(basePose(0, 0, 0), 0));
  EXPECT_FALSE(follower.update(std::nullopt, 0));
  EXPECT_FALSE(follower.cancel()) << "nothing to stop: the robot is not being driven";
}

TEST(GoalFollower, DrivesTowardsTheGoalWithinTheBurgerLimits) {
  GoalFollower follower;
  // Nearly ahead, a little to the left: the approach (forward, turning left).
  follower.setGoal({2.0, 0.1, 0.0}, 0);
  const std::optional<FollowCommand> c = follower.update(basePose(0, 0, 0), 0);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->stop, FollowStop::kNone);
  EXPECT_GT(c->command.v, 0);
  EXPECT_GT(c->command.w, 0);
  EXPECT_LE(std::abs(c->command.v), 0.22 + 1e-9);
  EXPECT_LE(std::abs(c->command.w), 2.84 + 1e-9);
  // A new goal replaces it: far off to the right, the servo turns in place first.
  follower.setGoal({0.5, -1.0, 0.0}, 0);
  const VelocityCommand turn = follower.update(basePose(0, 0, 0), 0)->command;
  EXPECT_EQ(turn.v, 0);
  EXPECT_LT(turn.w, 0);
}

TEST(GoalFollower, ReachedGivesZeroAndDropsTheGoal) {
  GoalFollower follower;
  const PlanarPose goal{0.6, -0.3, 1.0};
  follower.setGoal(goal, 0);
  PlanarPose base;
  constexpr double kDt = 1.0 / 30;
  std::optional<FollowCommand> c;
  int steps = 0;
  for (; steps < 30 * 60; ++steps) {
    c = follower.update(basePose(base.x, base.y, base.yaw), steps * kDt);
    ASSERT_TRUE(c);
    EXPECT_LE(std::abs(c->command.v), 0.22 + 1e-9);
    EXPECT_LE(std::abs(c->command.w), 2.84 + 1e-9);
    if (c->stop != FollowStop::kNone) break;
    base = drive(base, c->command, kDt);
  }
  ASSERT_TRUE(c);
  EXPECT_EQ(c->stop, FollowStop::kReached) << "after " << steps << " steps";
  EXPECT_TRUE(isZero(c->command));
  EXPECT_TRUE(c->step.done);
  EXPECT_NEAR(base.x, goal.x, 0.01);
  EXPECT_NEAR(base.y, goal.y, 0.01);
  EXPECT_FALSE(follower.active());
  EXPECT_FALSE(follower.update(basePose(0, 0, 0), 0)) << "done: nothing more is sent";
}

TEST(GoalFollower, LostTrackingGivesZeroAndDropsTheGoal) {
  GoalFollower follower;
  follower.setGoal({2.0, 0.0, 0.0}, 0);
  ASSERT_GT(follower.update(basePose(0, 0, 0), 0)->command.v, 0);
  const std::optional<FollowCommand> lost = follower.update(std::nullopt, 0);
  ASSERT_TRUE(lost);
  EXPECT_EQ(lost->stop, FollowStop::kLost);
  EXPECT_TRUE(isZero(lost->command));
  EXPECT_FALSE(follower.update(basePose(0, 0, 0), 0)) << "tracking back: no resume without a new goal";
  follower.setGoal({2.0, 0.0, 0.0}, 0);
  EXPECT_GT(follower.update(basePose(0, 0, 0), 0)->command.v, 0);
}

TEST(GoalFollower, NoFrameForTheTimeoutGivesZeroAndDropsTheGoal) {
  GoalFollowerOptions options;
  options.frame_timeout_s = 0.5;
  GoalFollower follower(options);
  follower.setGoal({2.0, 0.0, 0.0}, 10.0);
  EXPECT_FALSE(follower.checkFrames(10.4)) << "the first frame may take a moment";
  ASSERT_TRUE(follower.update(basePose(0, 0, 0), 10.4));
  EXPECT_FALSE(follower.checkFrames(10.8));
  const std::optional<FollowCommand> stalled = follower.checkFrames(11.0);
  ASSERT_TRUE(stalled);
  EXPECT_EQ(stalled->stop, FollowStop::kNoFrames);
  EXPECT_TRUE(isZero(stalled->command));
  EXPECT_FALSE(follower.active());
  EXPECT_FALSE(follower.checkFrames(20.0)) << "one zero command";
  EXPECT_FALSE(follower.update(basePose(0, 0, 0), 20.0)) << "frames again: no resume without a new goal";
}

TEST(GoalFollower, CancelGivesZeroAndDropsTheGoal) {
  GoalFollower follower;
  follower.setGoal({2.0, 0.0, 0.0}, 0);
  ASSERT_TRUE(follower.update(basePose(0, 0, 0), 0));
  const std::optional<FollowCommand> cancelled = follower.cancel();
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->stop, FollowStop::kCancelled);
  EXPECT_TRUE(isZero(cancelled->command));
  EXPECT_FALSE(follower.update(basePose(0, 0, 0), 0));
}

TEST(GoalFollower, PlanarGoalOfAMapPose) {
  const PlanarPose p = GoalFollower::planarGoal(basePose(1.5, -2.0, 0.7));
  EXPECT_NEAR(p.x, 1.5, 1e-12);
  EXPECT_NEAR(p.y, -2.0, 1e-12);
  EXPECT_NEAR(p.yaw, 0.7, 1e-12);
}
