#include "capture/replay_grabber.h"

#include <thread>

#include "camera/camera_file.h"
#include "core/error.h"

namespace plslam {

ReplayGrabber::ReplayGrabber(std::string dir, ReplayOptions options) : dir_(std::move(dir)), options_(std::move(options)) {}

void ReplayGrabber::open() {
  const std::string calib = options_.camera_file.empty() ? dir_ + "/camera.xml" : options_.camera_file;
  camera_ = loadCameraFile(calib);
  DatasetOptions dopt;
  dopt.max_frames = options_.max_frames;
  dopt.load_masks = false;  // a camera gives no instance masks
  dataset_ = std::make_unique<TumDataset>(TumDataset::open(dir_, camera_, dopt));
  closed_ = false;
  started_ = false;
  delivered_ = 0;
}

bool ReplayGrabber::grab(RgbdFrame* frame) {
  if (!dataset_) throw ConfigError("ReplayGrabber::grab before open(): " + dir_);
  if (closed_ || !dataset_->next(frame)) return false;
  if (!started_) {
    started_ = true;
    first_stamp_ = frame->t_ns;
    first_wall_ = std::chrono::steady_clock::now();
  } else if (options_.speed > 0) {
    // Sleep in short slices so close() from another thread ends the wait promptly.
    const auto due = first_wall_ + std::chrono::nanoseconds(static_cast<int64_t>(
                                       static_cast<double>(frame->t_ns - first_stamp_) / options_.speed));
    while (!closed_ && std::chrono::steady_clock::now() < due)
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(due - std::chrono::steady_clock::now(),
                                                                                 std::chrono::milliseconds(20)));
    if (closed_) return false;
  }
  frame->index = delivered_++;
  return true;
}

}  // namespace plslam
