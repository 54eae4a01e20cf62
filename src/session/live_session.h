// A SLAM session fed by pushing frames, for front ends that receive frames rather than
// pull them (the ROS node's subscriber callbacks; a ROS 2 node would use it the same way).
// It owns the System, a small queue in front of it, and the SLAM thread that pops and
// tracks; it reports each frame's outcome to a listener, gives snapshots of the sparse map,
// and writes the outputs of `plslam run` (run_outputs.h, the dense products) on request
// or at the end. Nothing here knows about any middleware.
//
// The queue drops the oldest waiting frame when tracking falls behind (counted), so
// tracking works on a recent frame; with drop_frames = false push() waits instead, which
// with a sequential System makes a session reproducible from the same frames.
//
// Thread safety: push(), save(), sparseMap() and counts() may be called from any thread,
// concurrently with the SLAM thread; start(), stop() and writeOutputs() from one owner
// thread. The listener runs on the SLAM thread: keep it short (publish, do not compute).
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/bounded_queue.h"
#include "core/frame.h"
#include "core/json.h"
#include "session/run_config.h"
#include "system/system.h"

namespace plslam {

struct SessionOptions {
  int queue = 2;            ///< frames waiting for tracking; beyond it the oldest is dropped
  bool drop_frames = true;  ///< false: push() waits for tracking instead of dropping
};

/// One tracked (or not) frame, as the listener sees it.
struct FrameOutcome {
  TimeNs t_ns = 0;
  TrackingStatus status = TrackingStatus::kNotInitialized;
  std::string reason;        ///< why, when not tracked
  bool tracked = false;
  SE3 T_w_c;                 ///< camera pose in plslam's world (the first camera's optical frame); valid when tracked
  int keyframes = 0;         ///< keyframes made in this session so far
  double tracking_ms = 0;    ///< System::feed time of this frame
};

struct SessionCounts {
  int received = 0;   ///< frames pushed
  int processed = 0;  ///< frames tracked or attempted
  int dropped = 0;    ///< frames discarded by the queue (received = processed + dropped + waiting)
  int tracked = 0;    ///< processed frames with a pose
};

/// Map points and 3D line endpoints in plslam's world frame.
struct SparseMapSnapshot {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;
};
/// Copies the landmarks of `map` under its lock.
SparseMapSnapshot sparseMapSnapshot(const Map& map);

class LiveSession {
 public:
  /// `config` as makeRunConfig gives it; its saved map (if any) is where tracking starts.
  LiveSession(const PinholeCamera& camera, RunConfig config, SessionOptions options = {});
  ~LiveSession();
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  /// Called with each frame's outcome on the SLAM thread. Set before start().
  void setFrameListener(std::function<void(const FrameOutcome&)> listener) { listener_ = std::move(listener); }
  /// Starts the System and the SLAM thread.
  void start();
  /// Hands a frame to the SLAM thread. False once stopped (the frame is not used).
  bool push(RgbdFrame frame);
  /// Writes the run outputs (trajectory so far, keyframes, sparse map, stats, config,
  /// map.plmap) into `dir` between two frames; the dense products are left to the end
  /// (they read the whole map without its lock: `plslam export` makes them from map.plmap).
  /// Throws what the writing throws.
  void save(const std::string& dir, const Json& stats_extra = nullptr);
  SparseMapSnapshot sparseMap() const { return sparseMapSnapshot(system_.map()); }
  SessionCounts counts() const;
  /// Ends the stream: the waiting frames are tracked, then the System finishes. Rethrows a
  /// failure of the SLAM thread. Calling it again does nothing.
  void stop();
  /// After stop(): the run outputs and, when `dense` and the options allow, the dense products.
  void writeOutputs(const std::string& dir, const Json& stats_extra, bool dense);

  const System& system() const { return system_; }

 private:
  void slamLoop();

  System system_;
  std::string config_yaml_;
  BoundedQueue<RgbdFrame> queue_;
  std::function<void(const FrameOutcome&)> listener_;
  std::thread thread_;
  std::mutex feed_mutex_;  // held while a frame is fed, so save() sees the System between frames
  std::exception_ptr failure_;
  std::atomic<int> received_{0}, processed_{0}, tracked_{0};
  int keyframes_ = 0;
  bool started_ = false, stopped_ = false;
};

}  // namespace plslam
