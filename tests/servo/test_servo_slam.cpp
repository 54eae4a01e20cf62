// The servo loops closed on what the robot's camera would see: views of the synthetic room
// rendered at the simulated base's true pose, tracked by plslam (goal servo on the SLAM
// pose) or searched for the AprilTag on the wall (tag servo on its detected pose). The
// final errors are the true ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <visp3/core/vpMath.h>

#include "camera/visp_conversion.h"
#include "servo_sim/rendered_sensors.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

void printFigures(const char* what, const SimulationResult& r) {
  std::printf("[servo figures] %s: %s, %d iterations (%d without a measurement), final error %.2f cm %.2f deg\n", what,
              r.converged ? "converged" : "NOT converged", r.iterations, r.blind_steps, 100 * r.position_error,
              vpMath::deg(std::abs(r.yaw_error)));
}

// A camera 1.2 m in front of the east-wall tag at its height, turned 10 degrees off it.
SE3 cameraFacingTheTag(const SE3& T_room_tag) {
  const SE3 T_tag_c(Eigen::Quaterniond(Eigen::AngleAxisd(vpMath::rad(10), Eigen::Vector3d::UnitY())),
                    Eigen::Vector3d(0.1, 0.0, -1.2));
  return T_room_tag * T_tag_c;
}

}  // namespace

TEST(TagRoom, DetectedTagPoseMatchesTheRenderedOne) {
  const TagRoom room(TagRoom::onEastWall(-0.8, 0.15));
  const SE3 T_room_c = cameraFacingTheTag(room.tagPose());
  const synth::RenderedFrame view = room.render(T_room_c, 0, 0);
  const TagPoseDetector detector(room.camera(), room.options().tag_id, room.options().tag_size);
  const std::optional<SE3> T_c_tag = detector.detect(view.bgr);
  ASSERT_TRUE(T_c_tag.has_value()) << "the tag 1.2 m ahead should be found";
  const SE3 truth = T_room_c.inverse() * room.tagPose();
  const SE3 error = truth.inverse() * *T_c_tag;
  std::printf("[servo figures] tag pose error at 1.2 m: %.2f mm %.3f deg\n", 1000 * error.translation().norm(),
              vpMath::deg(Eigen::AngleAxisd(error.rotation()).angle()));
  EXPECT_LT((T_c_tag->translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(vpMath::deg(Eigen::AngleAxisd(error.rotation()).angle()), 2.0);

  // Another tag id on the wall is not this detector's tag; nor is a view away from the wall.
  const TagPoseDetector other(room.camera(), room.options().tag_id + 1, room.options().tag_size);
  EXPECT_FALSE(other.detect(view.bgr).has_value());
  const SE3 turned_away = T_room_c * SE3(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())),
                                         Eigen::Vector3d::Zero());
  EXPECT_FALSE(detector.detect(room.render(turned_away, 0, 1).bgr).has_value());
}

TEST(ServoOnSlam, GoalServoOnSlamPosesReachesGoalsWithinFiveCentimetresAndThreeDegrees) {
  const TagRoom room(TagRoom::onEastWall(-0.8, 0.15));
  struct Case {
    PlanarPose start, goal;
  };
  const Case cases[] = {
      {{0, 0, 0}, {1.5, 0.5, vpMath::rad(90)}},     // ahead, turn at the end
      {{0, 0, 0}, {-1.0, 0.3, vpMath::rad(-120)}},  // behind: turn first
  };
  for (const Case& c : cases) {
    SimulationOptions sim;
    sim.start = c.start;
    const vpHomogeneousMatrix pMw = PlanarMap::toMatrix(c.start) * sim.bMc;  // the map: the camera at the start
    SlamPoses slam(room, defaultPlaneInRoom() * fromVisp(pMw), sim.dt);
    const SimulationResult r = simulatePoseServo(c.goal, PoseServoOptions(), sim, &slam);
    printFigures("goal on SLAM poses", r);
    std::printf("[servo figures] SLAM: %d frames, %d lost, %d keyframes, largest camera position error %.2f cm\n",
                slam.framesFed(), slam.framesLost(), slam.system().stats().keyframes, 100 * slam.maxPositionError());
    EXPECT_TRUE(r.converged) << "goal " << c.goal.x << "," << c.goal.y;
    EXPECT_LT(r.position_error, 0.05) << "goal " << c.goal.x << "," << c.goal.y;
    EXPECT_LT(vpMath::deg(std::abs(r.yaw_error)), 3.0) << "goal " << c.goal.x << "," << c.goal.y;
    EXPECT_GT(slam.maxPositionError(), 0) << "the poses should be SLAM's estimates, not the truth";
  }
}

TEST(ServoOnSlam, TagServoStopsAtTheStandoffFromDetectedTagPoses) {
  TagServoOptions options;
  options.standoff = 0.6;
  SimulationOptions sim;
  sim.start = {0, 0, vpMath::rad(-5)};  // the tag 22 degrees off the optical axis, near the image's edge
  const double tag_x = 2.0, tag_y = 0.6;
  const SE3 T_room_p = planeForTagOnEastWall(tag_x, tag_y);
  const vpHomogeneousMatrix pMo(vpTranslationVector(tag_x, tag_y, sim.bMc[2][3]), vpRotationMatrix());
  const TagRoom room(TagRoom::onEastWall(T_room_p.translation().y() + tag_y, sim.bMc[2][3]));
  DetectedTag sensor(room, T_room_p);
  const SimulationResult r = simulateTagServo(pMo, options, sim, nullptr, &sensor);
  printFigures("tag from detections", r);
  std::printf("[servo figures] tag detected in %d views, missed in %d\n", sensor.detections(), sensor.misses());
  EXPECT_TRUE(r.converged);
  EXPECT_GT(sensor.detections(), 0);
  EXPECT_LT(std::abs(r.position_error), 0.03) << "depth error";
  EXPECT_LT(vpMath::deg(std::abs(r.yaw_error)), 3.0) << "bearing of the tag";
  // The camera stands `standoff` from the tag centre.
  const double cx = r.final_pose.x + sim.bMc[0][3] * std::cos(r.final_pose.yaw);
  const double cy = r.final_pose.y + sim.bMc[0][3] * std::sin(r.final_pose.yaw);
  EXPECT_NEAR(std::hypot(tag_x - cx, tag_y - cy), options.standoff, 0.03);
}

// A tag never in view: the servo gets no measurement and the base stands still (TagServo::lost()).
TEST(ServoOnSlam, TagServoStandsStillWhileTheTagIsNotSeen) {
  SimulationOptions sim;
  sim.start = {0, 0, vpMath::rad(180)};  // facing away from the tag
  sim.max_time_s = 1.0;
  const double tag_x = 2.0, tag_y = 0.0;
  const SE3 T_room_p = planeForTagOnEastWall(tag_x, tag_y);
  const TagRoom room(TagRoom::onEastWall(T_room_p.translation().y() + tag_y, sim.bMc[2][3]));
  DetectedTag sensor(room, T_room_p);
  const vpHomogeneousMatrix pMo(vpTranslationVector(tag_x, tag_y, sim.bMc[2][3]), vpRotationMatrix());
  const SimulationResult r = simulateTagServo(pMo, TagServoOptions(), sim, nullptr, &sensor);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(sensor.detections(), 0);
  EXPECT_EQ(r.blind_steps, r.iterations);
  EXPECT_EQ(r.max_abs_v, 0.0);
  EXPECT_EQ(r.max_abs_w, 0.0);
  EXPECT_NEAR(r.final_pose.x, 0.0, 1e-12);
  EXPECT_NEAR(r.final_pose.yaw, sim.start.yaw, 1e-12);
}

TEST(ServoCli, PosesSlamServoesToTheDetectedTagAndRefusesSimulatedErrors) {
  auto r = test::runPlslam("servo --simulate --poses slam --tag 2,0.6 --standoff 0.6 --start 0,0,20 --sink udp:127.0.0.1:9");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("tag servo converged"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("tag detected in"), std::string::npos) << r.output;
  r = test::runPlslam("servo --simulate --poses slam --goal 1,0,0 --noise-position 0.01");
  EXPECT_EQ(r.status, 2) << r.output;
  r = test::runPlslam("servo --simulate --poses slam --goal 5,0,0");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("outside its floor"), std::string::npos) << r.output;
}
