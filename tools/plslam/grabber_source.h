// The frame source of `plslam live` and `plslam record`: the RealSense, or with --fake a
// recorded folder played at camera rate (--fake-speed).
#pragma once

#include <memory>

#include "args.h"
#include "capture/frame_grabber.h"

namespace plslam::cli {

/// Opens the source the parsed `args` ask for. ConfigError naming what is missing when the
/// RealSense is unavailable, or for a negative --fake-speed.
std::unique_ptr<FrameGrabber> openGrabber(const Args& args);

}  // namespace plslam::cli
