// What `plslam run` reads frames from, whatever holds them: a TUM-layout folder
// (io/dataset.h) or a ROS bag (ros1/bag_source.h, built only with ROS). The run loop,
// the evaluation and the statistics see only this interface, so the core never depends
// on where the frames were stored.
//
// Thread safety: none; use a source from one thread.
#pragma once

#include <cstddef>
#include <string>

#include "core/frame.h"
#include "core/trajectory.h"

namespace plslam {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// The next loadable frame in time order, skipping (and counting) bad ones; false at the end.
  virtual bool next(RgbdFrame* frame) = 0;
  /// Number of associated frames (before any per-frame skip).
  virtual size_t size() const = 0;
  /// The folder or file the frames come from, for messages and stats.json.
  virtual const std::string& location() const = 0;
  /// Ground truth poses T_w_c, empty when the source has none.
  virtual const Trajectory& groundtruth() const = 0;
  bool hasGroundtruth() const { return !groundtruth().empty(); }
  /// All frames skipped so far, whatever the reason.
  virtual int skippedTotal() const = 0;
  /// The frames skipped so far by reason, e.g. "2 unreadable image, 1 missing file" (empty: none).
  virtual std::string skippedText() const = 0;
};

}  // namespace plslam
