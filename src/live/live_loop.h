// The live loop: a grabber thread reads the camera and pushes each frame into a small
// drop-oldest queue (core/bounded_queue.h, kDropOldest); the caller's thread (the SLAM
// thread) pops and feeds the System. When tracking falls behind, the oldest waiting
// frames are dropped and counted, so tracking always works on a recent frame. Keyframes
// are never dropped: a frame becomes a keyframe inside System::feed, after the queue, and
// System's mapping queue blocks (kBlock) rather than drop.
//
// With drop_frames = false the grabber waits for tracking instead (nothing is dropped);
// with a sequential System this makes a live run reproducible from its recording:
// `plslam run --sequential` on the recorded folder gives the same trajectory.
//
// Every grabbed frame can be recorded (capture/tum_recorder.h), dropped ones included.
// The loop ends at the end of the stream, after max_frames grabbed frames, after
// duration_s seconds, or when `stop` returns true (Ctrl-C), whichever comes first.
#pragma once

#include <functional>
#include <string>

#include "capture/frame_grabber.h"
#include "capture/tum_recorder.h"
#include "core/json.h"
#include "system/system.h"

namespace plslam {

struct LiveOptions {
  int queue = 2;               ///< frames waiting for tracking; beyond it the oldest is dropped
  bool drop_frames = true;     ///< false: the grabber waits for tracking instead of dropping (deterministic)
  int max_frames = 0;          ///< stop after this many grabbed frames (0: no limit)
  double duration_s = 0;       ///< stop after this many seconds of capture (0: no limit)
  std::string record_dir;      ///< record every grabbed frame as a TUM folder here (empty: no recording)
  RecorderOptions recorder;    ///< how the recording is written
};

/// Why the loop ended.
enum class LiveStop { kEndOfStream, kFrameLimit, kDuration, kInterrupted };
const char* toString(LiveStop stop);

struct LiveStats {
  int grabbed = 0;     ///< frames read from the grabber
  int processed = 0;   ///< frames fed to the System
  int dropped = 0;     ///< frames discarded by the drop-oldest queue (grabbed = processed + dropped)
  int tracked = 0;     ///< processed frames with a pose
  int recorded = 0;    ///< frames written to record_dir
  double seconds = 0;  ///< wall time from the first grab to the last frame processed
  LiveStop stop = LiveStop::kEndOfStream;
};

struct LiveProgress {
  int grabbed = 0, processed = 0, dropped = 0, tracked = 0;
  double seconds = 0;
};

/// Runs the loop on an opened `grabber` and a started `slam` (whose camera must match the
/// grabber's images). `stop` (may be empty) is polled between frames; `progress` (may be
/// empty) is called on the SLAM thread at most every `progress_period_ms`. Does not call
/// slam->finish(). A grabber or recorder failure is rethrown once the loop has stopped.
/// `recording_camera` is the camera written with the recording (its depth scale quantises
/// the depth PNGs); by default the grabber's intrinsics.
LiveStats runLive(FrameGrabber* grabber, System* slam, const LiveOptions& options,
                  const std::function<bool()>& stop = {}, const std::function<void(const LiveProgress&)>& progress = {},
                  int progress_period_ms = 500, const PinholeCamera* recording_camera = nullptr);

/// LiveStats as JSON members for stats.json: live_grabbed, live_processed, live_dropped,
/// live_recorded, live_seconds, live_stop.
Json liveStatsJson(const LiveStats& stats);

}  // namespace plslam
