// tools/ros/turtlebot3_d435i.launch as roslaunch reads it (no master needed): the node is
// found through the package folder CMake writes in the build tree, the remaps and the
// parameters are what the README says.
#include <gtest/gtest.h>

#include "support/test_support.h"

using namespace plslam;

namespace {

test::CommandResult roslaunch(const std::string& arguments) {
  return test::runCommand("ROS_HOME=/tmp/plslam_tests/ros_home ROS_PACKAGE_PATH=" + test::binaryDir() +
                          "/ros roslaunch " + arguments + " " + test::sourceDir() + "/tools/ros/turtlebot3_d435i.launch" +
                          " colour:=/robot/rgb camera_to_base:=/tmp/c2b.yaml");
}

}  // namespace

TEST(RosLaunch, TurtleBot3LaunchRunsTheNodeWithItsRemapsAndParameters) {
  const auto args = roslaunch("--args /plslam");
  ASSERT_EQ(args.status, 0) << args.output;
  EXPECT_NE(args.output.find("/ros/plslam/plslam_ros"), std::string::npos) << args.output;
  EXPECT_NE(args.output.find("camera/color/image_raw:=/robot/rgb"), std::string::npos) << args.output;
  EXPECT_NE(args.output.find("camera/aligned_depth_to_color/image_raw:=/camera/aligned_depth_to_color/image_raw"),
            std::string::npos) << args.output;
  const auto params = roslaunch("--dump-params");
  ASSERT_EQ(params.status, 0) << params.output;
  EXPECT_NE(params.output.find("/plslam/odom_frame: odom"), std::string::npos) << params.output;
  EXPECT_NE(params.output.find("/plslam/base_frame: base_footprint"), std::string::npos) << params.output;
  EXPECT_NE(params.output.find("/plslam/camera_to_base: /tmp/c2b.yaml"), std::string::npos) << params.output;
}
