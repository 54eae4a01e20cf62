// Writes RGB-D frames as a ROS 1 bag in TUM's layout (bag_source.h reads it back):
//   /camera/rgb/image_color  rgb8
//   /camera/depth/image      32FC1, metres (0 = no reading)
//   /camera/rgb/camera_info  the camera, with every frame (a bag cut short still has it)
// each stamped with the frame's time, written in stamp order. For `plslam record --bag`.
//
// Thread safety: none; add() and close() from one thread.
#pragma once

#include <rosbag/bag.h>

#include <string>

#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/frame_recorder.h"
#include "ros1/bag_source.h"

namespace plslam::ros1 {

class BagWriter : public FrameRecorder {
 public:
  /// Creates `path` (overwritten if it exists). Throws IoError naming it when it cannot.
  BagWriter(std::string path, PinholeCamera camera, std::string frame_id = "camera_rgb_optical_frame");
  ~BagWriter() override;
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// Writes one frame (colour BGR 8-bit, depth CV_32F metres of the camera's size).
  /// Throws DataError for a frame that does not fit the camera, IoError when writing fails.
  void add(const RgbdFrame& frame) override;
  /// Closes the bag (its index is written then). Idempotent.
  void close() override;

  const std::string& location() const override { return path_; }
  int written() const override { return written_; }
  /// The topics written: TUM's layout, the first of knownBagLayouts().
  static BagTopics topics();

 private:
  std::string path_;
  PinholeCamera camera_;
  std::string frame_id_;
  rosbag::Bag bag_;
  int written_ = 0;
  bool open_ = false;
};

}  // namespace plslam::ros1
