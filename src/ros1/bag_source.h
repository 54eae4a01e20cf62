// Frames from a ROS 1 bag, behind the same FrameSource interface as a TUM folder, so that
// `plslam run --dataset FILE.bag` gives what the folder gives.
//
// Layouts, looked for in this order unless topics are given:
//   TUM RGB-D bags        /camera/rgb/image_color (rgb8), /camera/depth/image (32FC1 metres),
//                         /camera/rgb/camera_info
//   RealSense driver      /camera/color/image_raw, /camera/aligned_depth_to_color/image_raw
//                         (16UC1 millimetres), /camera/color/camera_info
// Colour and depth are paired by their header stamps exactly as TUM's associate.py pairs
// the lists of a folder (io/associate.h); the camera is the first camera_info. A frame
// whose messages cannot be converted is a counted, logged skip with its reason.
//
// open() reads the bag once to learn the stamps (instantiating every image: the header
// stamp is inside the message); next() reads each pair again.
//
// Thread safety: none; use one BagSource from one thread.
#pragma once

#include <rosbag/bag.h>
#include <rosbag/message_instance.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "io/frame_source.h"

namespace plslam::ros1 {

struct BagTopics {
  std::string colour, depth, camera_info;
};
/// TUM's layout, then the RealSense driver's.
std::vector<BagTopics> knownBagLayouts();

struct BagOptions {
  double max_difference_s = 0.02;  ///< colour/depth pairing window, seconds (associate.py's default)
  int max_frames = 0;              ///< keep only the first N associated frames; 0 = all
  std::string groundtruth_file;    ///< TUM trajectory to evaluate against (empty: none; a bag holds none)
  BagTopics topics;                ///< all empty: the first known layout the bag has
};

class BagSource : public FrameSource {
 public:
  /// Opens and indexes `path`. Throws IoError when it cannot be read or has none of the
  /// layouts (naming the topics it has), DataError without a camera_info or without a pair.
  static std::unique_ptr<BagSource> open(const std::string& path, const BagOptions& options = {});
  ~BagSource() override;

  bool next(RgbdFrame* frame) override;
  size_t size() const override { return pairs_.size(); }
  const std::string& location() const override { return path_; }
  const Trajectory& groundtruth() const override { return groundtruth_; }
  int skippedTotal() const override;
  std::string skippedText() const override;

  const PinholeCamera& camera() const { return camera_; }
  const BagTopics& topics() const { return topics_; }

 private:
  struct Stamped {
    TimeNs t_ns;
    rosbag::MessageInstance message;
  };
  BagSource() = default;
  void index();
  void pair(const BagOptions& options);
  std::string load(size_t i, RgbdFrame* frame) const;

  std::string path_;
  std::unique_ptr<rosbag::Bag> bag_;  // the message instances point into it: it never moves
  BagTopics topics_;
  PinholeCamera camera_;
  std::vector<Stamped> colour_, depth_;
  std::vector<std::pair<size_t, size_t>> pairs_;  // indices into colour_, depth_
  Trajectory groundtruth_;
  std::map<std::string, int> skipped_;  // reason -> frames
  size_t cursor_ = 0;
};

}  // namespace plslam::ros1
