// Live RGB-D frame sources. A FrameGrabber delivers RgbdFrame (colour BGR, depth in metres
// registered to the colour image, NaN where the sensor gave nothing) with the camera's
// intrinsics as a PinholeCamera.
//
// Implementations: the Intel RealSense through ViSP's vpRealSense2 (only when ViSP was
// built with librealsense2, VISP_HAVE_REALSENSE2) and ReplayGrabber, which plays a recorded
// TUM folder at camera rate (tests, and `plslam live --fake DIR`).
//
// Thread safety: one grabber is used from one thread at a time.
#pragma once

#include <memory>
#include <string>

#include "camera/pinhole_camera.h"
#include "core/frame.h"

namespace plslam {

class FrameGrabber {
 public:
  virtual ~FrameGrabber() = default;
  /// Starts streaming. Throws IoError / ConfigError naming the device when it cannot.
  virtual void open() = 0;
  /// The intrinsics of the colour image (depth is aligned to it); valid after open().
  virtual PinholeCamera intrinsics() const = 0;
  /// Waits for the next frame. Returns false at the end of the stream (a replay that is
  /// over) or after close(); throws IoError when the device fails.
  virtual bool grab(RgbdFrame* frame) = 0;
  /// Stops streaming; grab() returns false afterwards. Safe to call twice.
  virtual void close() = 0;
  /// A short label for messages ("realsense", "replay <dir>").
  virtual std::string name() const = 0;
};

struct RealSenseOptions {
  int width = 640;         ///< colour and depth width, pixels
  int height = 480;        ///< colour and depth height, pixels
  int fps = 30;            ///< frame rate, Hz
  std::string serial;      ///< device serial number (empty: the first device found)
};

/// True when this build can drive a RealSense (ViSP built with librealsense2).
bool realSenseAvailable();
/// Why live capture is unavailable and how to get it (empty when available).
std::string realSenseUnavailableMessage();
/// A RealSense grabber; throws ConfigError with realSenseUnavailableMessage() when this
/// build has no RealSense support.
std::unique_ptr<FrameGrabber> makeRealSenseGrabber(const RealSenseOptions& options = {});

}  // namespace plslam
