// Built instead of the ROS tests when the ROS 1 development packages were not found.
#include <gtest/gtest.h>

TEST(Ros, Skipped) {
  GTEST_SKIP() << "plslam was built without ROS 1 (PLSLAM_WITH_ROS off or the Debian ROS packages missing: "
                  "tools/setup.sh installs them): the bag and node tests are skipped";
}
