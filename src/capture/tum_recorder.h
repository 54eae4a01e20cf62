// Records RGB-D frames as a TUM RGB-D folder that `plslam run` replays exactly:
//
//   rgb/<stamp>.png     colour, 8-bit BGR PNG (lossless)
//   depth/<stamp>.png   depth, 16-bit PNG at the camera's depth scale (0 = no reading)
//   rgb.txt, depth.txt  "stamp path" lines, appended and flushed per frame, so a recording
//                       cut short (Ctrl-C, crash) is still a readable folder
//   camera.xml          the intrinsics and depth scale (camera/camera_file.h)
//
// Depth in metres is quantised back at the camera's depth scale: frames that came from
// such a file (a sensor or a replay) are written bit for bit.
//
// With `background`, PNG encoding runs on a writer thread fed by a blocking queue: add()
// only waits when the disk falls `queue` frames behind; nothing is dropped.
//
// Thread safety: add() and close() from one thread.
#pragma once

#include <cstdio>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "camera/pinhole_camera.h"
#include "core/bounded_queue.h"
#include "core/frame.h"
#include "core/frame_recorder.h"

namespace plslam {

struct RecorderOptions {
  bool background = true;   ///< encode and write on a writer thread
  int queue = 32;           ///< frames waiting for the writer before add() waits
  int png_compression = 1;  ///< PNG compression level 0-9 (lossless whatever the level; 1 is fast)
};

class TumRecorder : public FrameRecorder {
 public:
  /// Creates `dir` (and rgb/, depth/), writes camera.xml and the list headers. Throws
  /// IoError naming the folder when it cannot, or when it already holds rgb.txt.
  TumRecorder(std::string dir, PinholeCamera camera, RecorderOptions options = {});
  ~TumRecorder() override;
  TumRecorder(const TumRecorder&) = delete;
  TumRecorder& operator=(const TumRecorder&) = delete;

  /// Queues (or writes) one frame; its colour and depth must fit the camera. Throws
  /// IoError when a previous write failed.
  void add(const RgbdFrame& frame) override;
  /// Writes what is queued and closes the lists; rethrows a write failure. Idempotent.
  void close() override;

  const std::string& location() const override { return dir_; }
  /// Frames written so far (after close(): all of them).
  int written() const override;

 private:
  void write(const RgbdFrame& frame);
  void rethrowFailure();

  std::string dir_;
  PinholeCamera camera_;
  RecorderOptions options_;
  std::FILE* rgb_list_ = nullptr;
  std::FILE* depth_list_ = nullptr;
  std::unique_ptr<BoundedQueue<RgbdFrame>> queue_;
  std::thread writer_;
  mutable std::mutex mutex_;
  std::exception_ptr failure_;
  int written_ = 0;
  bool closed_ = false;
};

}  // namespace plslam
