// The node's message builders for the maps while running (tools/plslam_ros/ros_messages.h):
// the dense cloud's label and colour fields and the grid's cells and origin.
#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cstring>

#include "plslam_ros/ros_messages.h"

using namespace plslam;

TEST(RosMessages, DenseCloudCarriesClassLabelsAndSemanticColours) {
  std::vector<FusedPoint> cloud(2);
  cloud[0].p_w = Eigen::Vector3f(1, 2, 3);
  cloud[0].class_id = 3;
  cloud[1].p_w = Eigen::Vector3f(0, 0, 0);
  cloud[1].r = cloud[1].g = cloud[1].b = 200;  // no class: its grey
  const SE3 T_pub_map(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())), Eigen::Vector3d(0, 0, 1));
  std_msgs::Header header;
  header.frame_id = "map";
  const sensor_msgs::PointCloud2 msg = ros1::denseCloudMessage(cloud, T_pub_map, header);
  ASSERT_EQ(msg.width * msg.height, 2u);
  EXPECT_EQ(msg.header.frame_id, "map");
  sensor_msgs::PointCloud2ConstIterator<float> x(msg, "x"), rgb(msg, "rgb");
  sensor_msgs::PointCloud2ConstIterator<uint32_t> label(msg, "label");
  EXPECT_NEAR(x[0], -2, 1e-5);  // (1, 2, 3) turned 90 degrees about z, lifted 1 m
  EXPECT_NEAR(x[1], 1, 1e-5);
  EXPECT_NEAR(x[2], 4, 1e-5);
  EXPECT_EQ(*label, 4u);  // class 3 + 1
  uint32_t packed = 0;
  std::memcpy(&packed, &*rgb, 4);
  const Rgb c = classColour(3);
  EXPECT_EQ(packed, (uint32_t(c.r) << 16) | (uint32_t(c.g) << 8) | c.b);
  ++label, ++rgb;
  EXPECT_EQ(*label, 0u);  // no class
  std::memcpy(&packed, &*rgb, 4);
  EXPECT_EQ(packed, (200u << 16) | (200u << 8) | 200u);
}

TEST(RosMessages, GridKeepsCellsAndPlacesItsOrigin) {
  OccupancyGrid g;
  g.width = 3, g.height = 2, g.resolution = 0.1;
  g.origin = Eigen::Vector2d(-0.5, 0.2);
  g.cells = {OccupancyGrid::kFree, OccupancyGrid::kOccupied, OccupancyGrid::kUnknown,
             OccupancyGrid::kUnknown, OccupancyGrid::kFree, OccupancyGrid::kOccupied};
  const SE3 T_pub_map(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
  std_msgs::Header header;
  header.frame_id = "map";
  const nav_msgs::OccupancyGrid msg = ros1::gridMessage(g, T_pub_map, header);
  EXPECT_EQ(msg.info.width, 3u);
  EXPECT_EQ(msg.info.height, 2u);
  EXPECT_FLOAT_EQ(msg.info.resolution, 0.1f);
  EXPECT_NEAR(msg.info.origin.position.x, 0.5, 1e-12);
  EXPECT_NEAR(msg.info.origin.position.y, 0.2, 1e-12);
  ASSERT_EQ(msg.data.size(), 6u);
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(msg.data[i], g.cells[i]) << i;
}
