// The unit that flows from a frame source into the pipeline.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "core/time.h"

namespace plslam {

struct RgbdFrame {
  TimeNs t_ns = 0;       ///< colour image timestamp
  int index = -1;        ///< position in the source (0-based), for messages
  cv::Mat bgr;           ///< CV_8UC3, BGR as OpenCV loads it
  cv::Mat depth_m;       ///< CV_32FC1, metres, NaN where the sensor gave nothing
  cv::Mat instance_ids;  ///< optional CV_16UC1 instance mask (0 = none); see synth/README
  std::string name;      ///< file name or other short label for messages
};

/// A copy that owns its pixels. Anything handed to another thread gets one: callers reuse
/// their buffers (a grabber writes the next image into the same memory), and OpenCV's
/// reference counts are invisible to ThreadSanitizer, so shared buffers are never shared
/// across threads here.
inline RgbdFrame deepCopy(const RgbdFrame& f) {
  RgbdFrame c;
  c.t_ns = f.t_ns;
  c.index = f.index;
  c.bgr = f.bgr.clone();
  c.depth_m = f.depth_m.clone();
  c.instance_ids = f.instance_ids.clone();
  c.name = f.name;
  return c;
}

}  // namespace plslam
