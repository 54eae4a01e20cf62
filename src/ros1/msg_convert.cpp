#include "ros1/msg_convert.h"

#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam::ros1 {

namespace enc = sensor_msgs::image_encodings;

TimeNs toNs(const ros::Time& t) { return static_cast<TimeNs>(t.sec) * 1000000000LL + t.nsec; }

ros::Time toRosTime(TimeNs t_ns) {
  ros::Time t;
  t.sec = static_cast<uint32_t>(t_ns / 1000000000LL);
  t.nsec = static_cast<uint32_t>(t_ns % 1000000000LL);
  return t;
}

namespace {

// The message's pixels as a Mat header over its buffer (no copy), after checking its size.
cv::Mat view(const sensor_msgs::Image& msg, int type) {
  const size_t row = static_cast<size_t>(msg.width) * CV_ELEM_SIZE(type);
  if (msg.step < row || msg.data.size() < static_cast<size_t>(msg.step) * msg.height)
    throw DataError(str("image message ", msg.width, "x", msg.height, " ", msg.encoding, ": step ", msg.step,
                        " and ", msg.data.size(), " bytes do not hold its pixels"));
  if (msg.is_bigendian) throw DataError("image message: big-endian pixels are not supported");
  return cv::Mat(static_cast<int>(msg.height), static_cast<int>(msg.width), type,
                 const_cast<uint8_t*>(msg.data.data()), msg.step);
}

}  // namespace

cv::Mat colourToBgr(const sensor_msgs::Image& msg) {
  cv::Mat out;
  if (msg.encoding == enc::BGR8) out = view(msg, CV_8UC3).clone();
  else if (msg.encoding == enc::RGB8) cv::cvtColor(view(msg, CV_8UC3), out, cv::COLOR_RGB2BGR);
  else if (msg.encoding == enc::BGRA8) cv::cvtColor(view(msg, CV_8UC4), out, cv::COLOR_BGRA2BGR);
  else if (msg.encoding == enc::RGBA8) cv::cvtColor(view(msg, CV_8UC4), out, cv::COLOR_RGBA2BGR);
  else if (msg.encoding == enc::MONO8) cv::cvtColor(view(msg, CV_8UC1), out, cv::COLOR_GRAY2BGR);
  else throw DataError("colour image encoding '" + msg.encoding + "' is not supported (rgb8, bgr8, rgba8, bgra8, mono8)");
  return out;
}

cv::Mat depthToMetres(const sensor_msgs::Image& msg) {
  if (msg.encoding == enc::TYPE_16UC1 || msg.encoding == enc::MONO16) return plslam::depthToMetres(view(msg, CV_16UC1), 1000.0);
  if (msg.encoding != enc::TYPE_32FC1)
    throw DataError("depth image encoding '" + msg.encoding + "' is not supported (32FC1 metres, 16UC1 millimetres)");
  cv::Mat out = view(msg, CV_32FC1).clone();
  // REP-118: 0 and NaN both mean no depth; plslam uses NaN only.
  out.setTo(std::numeric_limits<float>::quiet_NaN(), out == 0);
  return out;
}

PinholeCamera cameraFromInfo(const sensor_msgs::CameraInfo& info) {
  PinholeCamera c;
  c.name = info.header.frame_id.empty() ? "camera_info" : info.header.frame_id;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = info.K[0];
  c.fy = info.K[4];
  c.cx = info.K[2];
  c.cy = info.K[5];
  c.depth_scale = 1000.0;
  bool any = false;
  for (double d : info.D) any = any || d != 0.0;
  if (any && info.distortion_model != "plumb_bob")
    throw DataError("camera_info: distortion model '" + info.distortion_model + "' is not supported (plumb_bob)");
  for (size_t i = 0; i < info.D.size() && i < c.dist.size(); ++i) c.dist[i] = info.D[i];
  c.validate("camera_info of " + c.name);
  return c;
}

sensor_msgs::Image bgrToImage(const cv::Mat& bgr, const std::string& encoding) {
  if (bgr.type() != CV_8UC3 || (encoding != enc::RGB8 && encoding != enc::BGR8))
    throw DataError("bgrToImage: expects CV_8UC3 and rgb8 or bgr8");
  sensor_msgs::Image msg;
  msg.height = bgr.rows;
  msg.width = bgr.cols;
  msg.encoding = encoding;
  msg.step = bgr.cols * 3;
  msg.data.resize(static_cast<size_t>(msg.step) * msg.height);
  cv::Mat dst(bgr.rows, bgr.cols, CV_8UC3, msg.data.data(), msg.step);
  if (encoding == enc::RGB8) cv::cvtColor(bgr, dst, cv::COLOR_BGR2RGB);
  else bgr.copyTo(dst);
  return msg;
}

sensor_msgs::Image depthToImage(const cv::Mat& depth_m, bool millimetres) {
  if (depth_m.type() != CV_32FC1) throw DataError("depthToImage: expects CV_32FC1 metres");
  sensor_msgs::Image msg;
  msg.height = depth_m.rows;
  msg.width = depth_m.cols;
  msg.encoding = millimetres ? enc::TYPE_16UC1 : enc::TYPE_32FC1;
  msg.step = depth_m.cols * (millimetres ? 2 : 4);
  msg.data.resize(static_cast<size_t>(msg.step) * msg.height);
  cv::Mat dst(depth_m.rows, depth_m.cols, millimetres ? CV_16UC1 : CV_32FC1, msg.data.data(), msg.step);
  if (!millimetres) {
    depth_m.copyTo(dst);
    return msg;
  }
  cv::Mat finite = depth_m.clone();
  finite.setTo(0, depth_m != depth_m);  // NaN -> 0: no depth
  finite.convertTo(dst, CV_16UC1, 1000.0);
  return msg;
}

sensor_msgs::CameraInfo infoFromCamera(const PinholeCamera& camera) {
  sensor_msgs::CameraInfo info;
  info.header.frame_id = camera.name;
  info.width = camera.width;
  info.height = camera.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(camera.dist.begin(), camera.dist.end());
  info.K = {camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {camera.fx, 0, camera.cx, 0, 0, camera.fy, camera.cy, 0, 0, 0, 1, 0};
  return info;
}

}  // namespace plslam::ros1
