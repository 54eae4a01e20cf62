// The RealSense grabber through ViSP's vpRealSense2: colour BGR8 and depth Z16 at the
// same size and rate, depth aligned to colour (rs2::align), intrinsics of the colour
// stream, and the device's depth scale. Compiled only when ViSP has librealsense2;
// elsewhere the factory throws ConfigError saying why and how to get it.
#include <visp3/core/vpConfig.h>

#include "capture/frame_grabber.h"
#include "core/error.h"
#include "core/log.h"

#if defined(VISP_HAVE_REALSENSE2)
#include <librealsense2/rs.hpp>
#include <visp3/sensor/vpRealSense2.h>

#include <cmath>
#include <vector>
#endif

namespace plslam {

#if defined(VISP_HAVE_REALSENSE2)
namespace {

const Logger kLog("capture");

class RealSenseGrabber : public FrameGrabber {
 public:
  explicit RealSenseGrabber(const RealSenseOptions& options) : options_(options), align_(RS2_STREAM_COLOR) {}
  ~RealSenseGrabber() override { close(); }

  void open() override {
    rs2::config config;
    if (!options_.serial.empty()) config.enable_device(options_.serial);
    config.enable_stream(RS2_STREAM_COLOR, options_.width, options_.height, RS2_FORMAT_BGR8, options_.fps);
    config.enable_stream(RS2_STREAM_DEPTH, options_.width, options_.height, RS2_FORMAT_Z16, options_.fps);
    try {
      if (!rs_.open(config)) throw IoError("RealSense: vpRealSense2::open failed");
    } catch (const std::exception& e) {
      throw IoError(str("RealSense", options_.serial.empty() ? "" : " " + options_.serial, ": cannot start ",
                        options_.width, "x", options_.height, " @", options_.fps, " Hz colour+depth: ", e.what()));
    }
    // Depth is aligned to colour, so the colour intrinsics describe both images.
    const rs2_intrinsics in = rs_.getIntrinsics(RS2_STREAM_COLOR);
    camera_.name = "realsense" + (options_.serial.empty() ? std::string() : "_" + options_.serial);
    camera_.width = in.width;
    camera_.height = in.height;
    camera_.fx = in.fx;
    camera_.fy = in.fy;
    camera_.cx = in.ppx;
    camera_.cy = in.ppy;
    if (in.model == RS2_DISTORTION_BROWN_CONRADY || in.model == RS2_DISTORTION_INVERSE_BROWN_CONRADY ||
        in.model == RS2_DISTORTION_MODIFIED_BROWN_CONRADY) {
      // librealsense's coefficient order is OpenCV's: k1 k2 p1 p2 k3.
      for (int i = 0; i < 5; ++i) camera_.dist[i] = in.coeffs[i];
    } else if (in.model != RS2_DISTORTION_NONE) {
      kLog.warn(str("RealSense colour distortion model ", rs2_distortion_to_string(in.model),
                    " is not Brown-Conrady: ignored (calibrate with plslam calibrate for a better model)"));
    }
    camera_.depth_scale = 1.0 / rs_.getDepthScale();  // metres per unit -> units per metre
    camera_.validate("RealSense colour intrinsics");
    colour_.assign(static_cast<size_t>(camera_.width) * camera_.height * 3, 0);
    depth_.assign(static_cast<size_t>(camera_.width) * camera_.height * 2, 0);
    open_ = true;
    index_ = 0;
    kLog.info(str("RealSense open: ", camera_.width, "x", camera_.height, " fx ", camera_.fx, " fy ", camera_.fy,
                  " depth scale ", camera_.depth_scale, " units/m"));
  }

  PinholeCamera intrinsics() const override { return camera_; }

  bool grab(RgbdFrame* frame) override {
    if (!open_) return false;
    double ts_ms = 0;
    try {
      rs_.acquire(colour_.data(), depth_.data(), nullptr, nullptr, &align_, &ts_ms);
    } catch (const std::exception& e) {
      throw IoError(str("RealSense: frame ", index_, " could not be acquired: ", e.what()));
    }
    frame->t_ns = static_cast<TimeNs>(std::llround(ts_ms * 1e6));
    frame->index = index_++;
    frame->bgr = cv::Mat(camera_.height, camera_.width, CV_8UC3, colour_.data()).clone();
    const cv::Mat raw(camera_.height, camera_.width, CV_16UC1, depth_.data());
    frame->depth_m = depthToMetres(raw, camera_.depth_scale);
    frame->instance_ids.release();
    frame->name = str("realsense#", frame->index);
    return true;
  }

  void close() override {
    if (!open_) return;
    open_ = false;
    rs_.close();
  }

  std::string name() const override { return "realsense"; }

 private:
  RealSenseOptions options_;
  vpRealSense2 rs_;
  rs2::align align_;
  PinholeCamera camera_;
  std::vector<unsigned char> colour_, depth_;
  bool open_ = false;
  int index_ = 0;
};

}  // namespace

std::unique_ptr<FrameGrabber> makeRealSenseGrabber(const RealSenseOptions& options) {
  return std::make_unique<RealSenseGrabber>(options);
}

#else

std::unique_ptr<FrameGrabber> makeRealSenseGrabber(const RealSenseOptions&) {
  throw ConfigError(realSenseUnavailableMessage());
}

#endif

}  // namespace plslam
