// The pose of one tag36h11 AprilTag in a camera image: the calibration module's apriltag
// detector (edge-refined corners) and a PnP on the four corners with the tag's size
// (cv::solvePnP, SOLVEPNP_IPPE_SQUARE: the planar square solution).
//
// Thread safety: none (the apriltag detector keeps state); one per thread.
#pragma once

#include <opencv2/core.hpp>
#include <optional>

#include "calibration/detect.h"
#include "camera/pinhole_camera.h"
#include "core/se3.h"

namespace plslam {

class TagPoseDetector {
 public:
  /// tag_size: edge of the tag's black border, metres.
  TagPoseDetector(const PinholeCamera& camera, int tag_id, double tag_size);

  /// T_c_tag: the tag frame (centre, x right as printed, y down, z into the tag) in the
  /// camera, or nullopt when the tag is not found whole in the image.
  std::optional<SE3> detect(const cv::Mat& image) const;

 private:
  PinholeCamera camera_;
  double tag_size_;
  calib::TargetDetector detector_;
};

}  // namespace plslam
