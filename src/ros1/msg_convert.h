// Conversions between ROS 1 messages and plslam's types, shared by the bag reader and
// the ROS node. Both directions live here so that they round-trip in one test.
//
// Depth follows REP-118: 32FC1 in metres (NaN or 0 where there is none), or 16UC1 in
// millimetres (0 where there is none), which is what the RealSense and Orbbec drivers
// publish for depth registered to colour.
#pragma once

#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <opencv2/core.hpp>
#include <string>

#include "camera/pinhole_camera.h"
#include "core/time.h"

namespace plslam::ros1 {

TimeNs toNs(const ros::Time& t);
ros::Time toRosTime(TimeNs t_ns);

/// A colour image (rgb8, bgr8, rgba8, bgra8 or mono8) as an owned CV_8UC3 BGR image.
/// Throws DataError naming the encoding otherwise, or for a buffer shorter than it claims.
cv::Mat colourToBgr(const sensor_msgs::Image& msg);
/// A depth image (32FC1 metres, 16UC1 or mono16 millimetres) as owned CV_32FC1 metres with
/// NaN where there is no depth. Throws DataError for any other encoding.
cv::Mat depthToMetres(const sensor_msgs::Image& msg);
/// The pinhole camera of a camera_info: K, the image size, and D for the plumb_bob model
/// (k1 k2 p1 p2 k3). Throws DataError for another model with non-zero coefficients or an
/// invalid camera. depth_scale is 1000 (the millimetres of 16UC1 depth).
PinholeCamera cameraFromInfo(const sensor_msgs::CameraInfo& info);

/// The other direction, for recording and tests: BGR as `encoding` (rgb8 or bgr8).
sensor_msgs::Image bgrToImage(const cv::Mat& bgr, const std::string& encoding = "rgb8");
/// Metres (NaN: none) as 32FC1 metres, or as 16UC1 millimetres (rounded) when `millimetres`.
sensor_msgs::Image depthToImage(const cv::Mat& depth_m, bool millimetres);
sensor_msgs::CameraInfo infoFromCamera(const PinholeCamera& camera);

}  // namespace plslam::ros1
