// The free-space test (free_space_check.h): points moved into an earlier camera whose depth
// image saw a wall, a near box on it, and a hole without depth.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "dynamic/free_space_check.h"
#include "synth/scene.h"

namespace plslam {
namespace {

PinholeCamera camera() { return synth::syntheticCamera(640, 480); }  // fx = fy = 525, centre (319.5, 239.5)

// The earlier frame saw a wall at 3 m, a box at 1.5 m over columns 300-339, and nothing
// (no depth) over columns 500-539.
cv::Mat earlierDepth() {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(3.0f));
  depth.colRange(300, 340).setTo(1.5f);
  depth.colRange(500, 540).setTo(std::numeric_limits<float>::quiet_NaN());
  return depth;
}

// The point seen at pixel (u, 240) at depth z by a camera that has not moved.
Eigen::Vector3d at(double u, double z) { return camera().unprojectIdeal({u, 240.0}, z); }

FreeSpaceOptions on() {
  FreeSpaceOptions o;
  o.enabled = true;
  return o;
}

TEST(FreeSpace, APointInFrontOfWhatTheEarlierFrameSawHasArrived) {
  const std::vector<uint8_t> r =
      pointsInEarlierFreeSpace({at(100, 1.5), at(100, 2.5)}, SE3(), earlierDepth(), camera(), {}, on());
  EXPECT_EQ(r, (std::vector<uint8_t>{1, 1}));
}

TEST(FreeSpace, PointsOnOrBehindWhatWasSeenGetNoVerdict) {
  // On the wall, behind it (hidden then), and within the noise in front of it (3 m: 4 sigma
  // of both readings is about 0.13 m).
  const std::vector<uint8_t> r = pointsInEarlierFreeSpace({at(100, 3.0), at(100, 4.0), at(100, 2.95)}, SE3(),
                                                          earlierDepth(), camera(), {}, on());
  EXPECT_EQ(r, (std::vector<uint8_t>{0, 0, 0}));
}

TEST(FreeSpace, AnOutlineTakesTheNearestDepthAroundItsProjection) {
  // Two pixels left of the box, a point at the box's depth: the wall is behind it, but the
  // box is within the window, so it may be the box's edge seen with a slightly wrong motion.
  const std::vector<uint8_t> near_edge =
      pointsInEarlierFreeSpace({at(298, 1.5)}, SE3(), earlierDepth(), camera(), {}, on());
  EXPECT_EQ(near_edge[0], 0);
  const std::vector<uint8_t> far_from_edge =
      pointsInEarlierFreeSpace({at(290, 1.5)}, SE3(), earlierDepth(), camera(), {}, on());
  EXPECT_EQ(far_from_edge[0], 1);
}

TEST(FreeSpace, TheCameraMotionMovesThePointIntoTheEarlierImage) {
  // The camera moved since: a point at 1.5 m lies 0.5 m further along x for the earlier
  // camera, 525 * 0.5 / 1.5 = 175 px to the right. From pixel 100 it lands at 275, in front
  // of the wall (arrived); from pixel 140 at 315, on the box, no nearer than the box. Without
  // the motion both would be in front of the wall.
  const SE3 T_earlier_cur(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0, 0));
  const std::vector<uint8_t> r =
      pointsInEarlierFreeSpace({at(100, 1.5), at(140, 1.5)}, T_earlier_cur, earlierDepth(), camera(), {}, on());
  EXPECT_EQ(r, (std::vector<uint8_t>{1, 0}));
  const std::vector<uint8_t> unmoved =
      pointsInEarlierFreeSpace({at(100, 1.5), at(140, 1.5)}, SE3(), earlierDepth(), camera(), {}, on());
  EXPECT_EQ(unmoved, (std::vector<uint8_t>{1, 1}));
}

TEST(FreeSpace, NoDepthOutsideTheImageOrOffGivesNoVerdict) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Eigen::Vector3d> points = {at(520, 1.0), at(100, nan), Eigen::Vector3d(10, 0, 1),
                                               Eigen::Vector3d(0, 0, -1)};
  EXPECT_EQ(pointsInEarlierFreeSpace(points, SE3(), earlierDepth(), camera(), {}, on()),
            (std::vector<uint8_t>{0, 0, 0, 0}));
  EXPECT_EQ(pointsInEarlierFreeSpace({at(100, 1.5)}, SE3(), earlierDepth(), camera(), {}, FreeSpaceOptions{}),
            (std::vector<uint8_t>{0}))
      << "off by default";
}

TEST(FreeSpace, ADepthImageOfAnotherTypeOrSizeIsRefused) {
  EXPECT_THROW(pointsInEarlierFreeSpace({}, SE3(), cv::Mat(480, 640, CV_16UC1), camera(), {}, on()), DataError);
  EXPECT_THROW(pointsInEarlierFreeSpace({}, SE3(), cv::Mat(240, 320, CV_32FC1), camera(), {}, on()), DataError);
}

}  // namespace
}  // namespace plslam
