// plslam's products as ROS 1 messages: pure functions, no node state, so the adapter
// only decides what to publish and when.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/Marker.h>

#include <string>

#include "core/se3.h"
#include "dense/cloud_fusion.h"
#include "dense/occupancy_grid.h"
#include "session/live_session.h"

namespace plslam::ros1 {

geometry_msgs::Pose toPose(const SE3& T);
SE3 fromPose(const geometry_msgs::Pose& pose);
geometry_msgs::Transform toTransform(const SE3& T);
SE3 fromTransform(const geometry_msgs::Transform& t);

/// The map points, moved into the map frame (p_map = T_map_world * p_w): x, y, z float32 fields.
sensor_msgs::PointCloud2 pointsMessage(const SparseMapSnapshot& map, const SE3& T_map_world, const std_msgs::Header& header);
/// The 3D lines as one LINE_LIST marker (two points per line) in the map frame.
visualization_msgs::Marker linesMessage(const SparseMapSnapshot& map, const SE3& T_map_world, const std_msgs::Header& header);
/// The dense semantic cloud (points in the products' map frame, moved by T_pub_map into the
/// published frame): x, y, z float32; rgb float32 (packed 0x00RRGGBB, as PCL and RViz
/// read it) holding the semantic colour (dense/cloud_fusion.h: palette colour of the class,
/// grey luminance without one); label uint32 = class id + 1 (0: no class), as in
/// dense_cloud.pcd.
sensor_msgs::PointCloud2 denseCloudMessage(const std::vector<FusedPoint>& cloud, const SE3& T_pub_map,
                                           const std_msgs::Header& header);
/// The 2D grid (its floor frame = the products' map frame, moved by T_pub_map): same cells
/// (-1 unknown, 0 free, 100 occupied; row 0 = smallest y), origin the pose of cell (0, 0)'s
/// corner.
nav_msgs::OccupancyGrid gridMessage(const OccupancyGrid& grid, const SE3& T_pub_map, const std_msgs::Header& header);

/// The frame's tracking status and the session's counters, as one DiagnosticStatus named
/// "plslam: tracking" (OK when tracked, WARN otherwise).
diagnostic_msgs::DiagnosticArray statusMessage(const FrameOutcome& frame, const SessionCounts& counts,
                                               double latency_ms, const std_msgs::Header& header);

}  // namespace plslam::ros1
