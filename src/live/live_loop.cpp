#include "live/live_loop.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <memory>
#include <optional>
#include <thread>

#include "core/bounded_queue.h"
#include "core/error.h"
#include "core/json.h"
#include "core/log.h"

namespace plslam {

namespace {
const Logger kLog("live");
}

const char* toString(LiveStop stop) {
  switch (stop) {
    case LiveStop::kEndOfStream: return "end_of_stream";
    case LiveStop::kFrameLimit: return "frame_limit";
    case LiveStop::kDuration: return "duration";
    case LiveStop::kInterrupted: return "interrupted";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// The grabber thread's loop: grab, record, push, until Ctrl-C, a SLAM failure, the frame or
/// time limit or the end of the stream (`stop_reason` says which; not set on a SLAM failure).
void grabUntilStopped(FrameGrabber* grabber, FrameRecorder* recorder, BoundedQueue<RgbdFrame>& queue,
                      const LiveOptions& options, const std::function<bool()>& stop,
                      const std::atomic<bool>& slam_failed, std::atomic<int>& grabbed, Clock::time_point start,
                      LiveStop* stop_reason) {
  RgbdFrame frame;
  while (true) {
    if (stop && stop()) {
      *stop_reason = LiveStop::kInterrupted;
      break;
    }
    if (slam_failed) break;
    if (options.max_frames > 0 && grabbed >= options.max_frames) {
      *stop_reason = LiveStop::kFrameLimit;
      break;
    }
    if (options.duration_s > 0 && secondsSince(start) >= options.duration_s) {
      *stop_reason = LiveStop::kDuration;
      break;
    }
    if (!grabber->grab(&frame)) {
      *stop_reason = LiveStop::kEndOfStream;
      break;
    }
    if (recorder) recorder->add(frame);
    ++grabbed;
    queue.push(frame);
    frame = RgbdFrame();  // the queued frame owns its images now
  }
}

/// The SLAM thread's loop: pop and track until the stream is closed and drained, reporting
/// progress every progress_period_ms.
void trackUntilDrained(System* slam, BoundedQueue<RgbdFrame>& queue, const std::atomic<int>& grabbed,
                       const std::function<void(const LiveProgress&)>& progress, int progress_period_ms,
                       Clock::time_point start, LiveStats* stats) {
  Clock::time_point last_progress = Clock::now();
  while (auto frame = queue.pop()) {
    const TrackingResult r = slam->feed(*frame);
    ++stats->processed;
    if (isTracked(r.status)) ++stats->tracked;
    if (progress && Clock::now() - last_progress >= std::chrono::milliseconds(progress_period_ms)) {
      last_progress = Clock::now();
      progress({grabbed.load(), stats->processed, static_cast<int>(queue.dropped()), stats->tracked, secondsSince(start)});
    }
  }
}

}  // namespace

LiveStats runLive(FrameGrabber* grabber, System* slam, const LiveOptions& options, const std::function<bool()>& stop,
                  const std::function<void(const LiveProgress&)>& progress, int progress_period_ms,
                  const PinholeCamera* recording_camera) {
  BoundedQueue<RgbdFrame> queue(options.queue, options.drop_frames ? QueuePolicy::kDropOldest : QueuePolicy::kBlock);
  std::unique_ptr<FrameRecorder> recorder;
  if (!options.record_dir.empty())
    recorder = std::make_unique<TumRecorder>(options.record_dir,
                                             recording_camera ? *recording_camera : grabber->intrinsics(),
                                             options.recorder);

  LiveStats stats;
  std::atomic<int> grabbed{0};
  std::atomic<bool> slam_failed{false};
  std::exception_ptr grab_failure;
  const Clock::time_point start = Clock::now();

  // Grabber thread: ends the stream by closing the queue.
  std::thread grab_thread([&] {
    try {
      grabUntilStopped(grabber, recorder.get(), queue, options, stop, slam_failed, grabbed, start, &stats.stop);
    } catch (...) {
      grab_failure = std::current_exception();
    }
    queue.close();
  });

  // SLAM thread (this one).
  std::exception_ptr slam_failure;
  try {
    trackUntilDrained(slam, queue, grabbed, progress, progress_period_ms, start, &stats);
  } catch (...) {
    slam_failure = std::current_exception();
    slam_failed = true;
    queue.close();
  }
  grab_thread.join();
  stats.seconds = secondsSince(start);
  stats.grabbed = grabbed.load();
  stats.dropped = static_cast<int>(queue.dropped());
  if (recorder) {
    recorder->close();
    stats.recorded = recorder->written();
  }
  if (progress) progress({stats.grabbed, stats.processed, stats.dropped, stats.tracked, stats.seconds});
  if (slam_failure) std::rethrow_exception(slam_failure);
  if (grab_failure) std::rethrow_exception(grab_failure);
  kLog.info(str("live: grabbed ", stats.grabbed, ", processed ", stats.processed, ", dropped ", stats.dropped,
                " in ", stats.seconds, " s (", toString(stats.stop), ")"));
  return stats;
}

Json liveStatsJson(const LiveStats& s) {
  return {{"live_grabbed", s.grabbed},   {"live_processed", s.processed}, {"live_dropped", s.dropped},
          {"live_recorded", s.recorded}, {"live_seconds", s.seconds},     {"live_stop", toString(s.stop)}};
}

}  // namespace plslam
