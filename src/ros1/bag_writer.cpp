#include "ros1/bag_writer.h"

#include <rosbag/exceptions.h>

#include "core/error.h"
#include "core/log.h"
#include "ros1/msg_convert.h"

namespace plslam::ros1 {

BagTopics BagWriter::topics() { return knownBagLayouts().front(); }

BagWriter::BagWriter(std::string path, PinholeCamera camera, std::string frame_id)
    : path_(std::move(path)), camera_(std::move(camera)), frame_id_(std::move(frame_id)) {
  try {
    bag_.open(path_, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw IoError(str(path_, ": cannot create the bag: ", e.what()));
  }
  open_ = true;
}

BagWriter::~BagWriter() {
  try {
    close();
  } catch (const std::exception&) {
    // Destroyed on an error path: the caller reports the first error.
  }
}

void BagWriter::add(const RgbdFrame& frame) {
  if (!open_) throw Error("BagWriter::add after close()");
  if (frame.bgr.cols != camera_.width || frame.bgr.rows != camera_.height || frame.depth_m.size() != frame.bgr.size())
    throw DataError(str(path_, ": frame ", frame.index, " is ", frame.bgr.cols, "x", frame.bgr.rows, ", the camera ",
                        camera_.width, "x", camera_.height));
  const ros::Time stamp = toRosTime(frame.t_ns);
  sensor_msgs::CameraInfo info = infoFromCamera(camera_);
  sensor_msgs::Image colour = bgrToImage(frame.bgr, "rgb8");
  sensor_msgs::Image depth = depthToImage(frame.depth_m, false);  // 32FC1 metres, as TUM's bags
  colour.header.stamp = depth.header.stamp = info.header.stamp = stamp;
  colour.header.seq = depth.header.seq = info.header.seq = static_cast<uint32_t>(written_);
  colour.header.frame_id = depth.header.frame_id = info.header.frame_id = frame_id_;
  const BagTopics t = topics();
  try {
    bag_.write(t.camera_info, stamp, info);
    bag_.write(t.colour, stamp, colour);
    bag_.write(t.depth, stamp, depth);
  } catch (const rosbag::BagException& e) {
    throw IoError(str(path_, ": cannot write frame ", frame.index, ": ", e.what()));
  }
  ++written_;
}

void BagWriter::close() {
  if (!open_) return;
  open_ = false;
  try {
    bag_.close();
  } catch (const rosbag::BagException& e) {
    throw IoError(str(path_, ": cannot close the bag: ", e.what()));
  }
}

}  // namespace plslam::ros1
