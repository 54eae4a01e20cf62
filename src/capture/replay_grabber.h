// A FrameGrabber that plays a recorded TUM folder (io/dataset.h) as if it were a camera:
// frames come at the pace of their stamps (the grabber sleeps until each frame is due), so
// a consumer slower than the recording falls behind exactly as with a live sensor. The
// frames keep their recorded stamps, so a recording of the replay is the same sequence.
//
// Thread safety: one thread calls open/grab; close() may be called from another thread
// to end a grab() that is sleeping.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "capture/frame_grabber.h"
#include "io/dataset.h"

namespace plslam {

struct ReplayOptions {
  std::string camera_file;   ///< camera file (empty: <dir>/camera.xml)
  double speed = 1.0;        ///< playback speed relative to the stamps; 0 = as fast as the consumer reads
  int max_frames = 0;        ///< stop after this many frames (0 = the whole folder)
};

class ReplayGrabber : public FrameGrabber {
 public:
  explicit ReplayGrabber(std::string dir, ReplayOptions options = {});
  void open() override;
  PinholeCamera intrinsics() const override { return camera_; }
  bool grab(RgbdFrame* frame) override;
  void close() override { closed_ = true; }
  std::string name() const override { return "replay " + dir_; }
  /// Frames of the folder that could not be loaded (skipped, see TumDataset).
  int skipped() const { return dataset_ ? dataset_->skippedTotal() : 0; }

 private:
  std::string dir_;
  ReplayOptions options_;
  PinholeCamera camera_;
  std::unique_ptr<TumDataset> dataset_;
  std::atomic<bool> closed_{false};
  bool started_ = false;
  int delivered_ = 0;
  TimeNs first_stamp_ = 0;
  std::chrono::steady_clock::time_point first_wall_;
};

}  // namespace plslam
