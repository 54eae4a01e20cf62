// Where recorded RGB-D frames go: a TUM RGB-D folder (capture/tum_recorder.h) or, built
// with ROS, a bag in TUM's layout (ros1/bag_writer.h). `plslam record` and the live loop
// write through this, so a new format is one more implementation, not one more branch.
//
// Thread safety: none; add() and close() from one thread.
#pragma once

#include <string>

#include "core/frame.h"

namespace plslam {

class FrameRecorder {
 public:
  virtual ~FrameRecorder() = default;
  /// Writes (or queues) one frame. Throws DataError, and records nothing of it, when its
  /// colour or depth does not fit the recorder's camera; IoError when writing failed.
  virtual void add(const RgbdFrame& frame) = 0;
  /// Writes what is queued and closes the recording; rethrows a write failure. Idempotent.
  virtual void close() = 0;
  /// Frames written so far (after close(): all of them).
  virtual int written() const = 0;
  /// The folder or file written, for messages.
  virtual const std::string& location() const = 0;
};

}  // namespace plslam
