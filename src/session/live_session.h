// A SLAM session fed by pushing frames, for front ends that receive frames rather than
// pull them (the ROS node's subscriber callbacks; a ROS 2 node would use it the same way).
// It owns the System, a small queue in front of it, and the SLAM thread that pops and
// tracks; it reports each frame's outcome to a listener, gives snapshots of the sparse map,
// keeps the dense maps up to date while it runs (session/live_maps.h: every
// dense.live_every_keyframes keyframes or dense.live_every_s seconds, written into
// SessionOptions::maps_dir and handed to a maps listener), and writes the outputs of
// `plslam run` (run_outputs.h, the dense products) on request or at the end. Nothing here
// knows about any middleware.
//
// The queue drops the oldest waiting frame when tracking falls behind (counted), so
// tracking works on a recent frame; with drop_frames = false push() waits instead, which
// with a sequential System makes a session reproducible from the same frames.
//
// The map frame (core/map_frame.h) is fixed once: a saved map's own frame; else the floor
// the maps while running find in the dense cloud (when they run); else the floor of the map
// points after the first map_frame_keyframes keyframes; at the latest at the first save().
// Every output written afterwards (save(), writeOutputs(): map_frame.yaml, trajectory_map.txt,
// trajectory_base.txt, the dense products) is in it, so that a front end publishing poses in
// it (FrameOutcome::T_map_world) and the files agree.
//
// reset() drops the map between two frames and starts a new System (an empty map, mapping,
// a new world and map frame: the next frame initialises it), for a robot that was carried
// or whose map went wrong; the outputs and poses from then on are the new map's only.
//
// Thread safety: push(), save(), reset(), sparseMap(), mapFrame() and counts() may be called
// from any thread, concurrently with the SLAM thread; start(), stop() and writeOutputs()
// from one owner thread. The frame listener runs on the SLAM thread, the maps listener on the maps
// thread: keep them short (publish, do not compute).
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/bounded_queue.h"
#include "core/frame.h"
#include "core/map_frame.h"
#include "core/trajectory.h"
#include "session/live_maps.h"
#include "core/json.h"
#include "session/run_config.h"
#include "system/system.h"

namespace plslam {

struct SessionOptions {
  int queue = 2;            ///< frames waiting for tracking; beyond it the oldest is dropped
  bool drop_frames = true;  ///< false: push() waits for tracking instead of dropping
  int map_frame_keyframes = 5;  ///< without maps while running: the map frame is fixed from the map points after this many keyframes
  bool live_maps = true;    ///< maps while running (also needs dense.enabled and a dense.live_every_* > 0)
  std::string maps_dir;     ///< where the maps while running are written (empty: not written, only listened to)
};

/// One tracked (or not) frame, as the listener sees it.
struct FrameOutcome {
  TimeNs t_ns = 0;
  TrackingStatus status = TrackingStatus::kNotInitialized;
  std::string reason;        ///< why, when not tracked
  bool tracked = false;
  SE3 T_w_c;                 ///< camera pose in plslam's world (the first camera's optical frame); valid when tracked
  int keyframes = 0;         ///< keyframes made in this session's map so far (0 again after a reset)
  int resets = 0;            ///< reset() calls before this frame: a new value starts a new map, world and path
  bool localizing = false;   ///< tracked without changing the map (setLocalization)
  double tracking_ms = 0;    ///< System::feed time of this frame
  bool map_frame_fixed = false;  ///< T_map_world is the session's fixed map frame (else none yet)
  SE3 T_map_world;           ///< the map frame of the outputs, when map_frame_fixed
  /// Set on the first frame after a loop correction changed the map (Map::corrections()):
  /// every tracked frame's pose so far, corrected (SLAM world), so that a path drawn from
  /// the earlier outcomes can be redrawn.
  std::shared_ptr<const Trajectory> revised;
};

/// Frame counts of the whole session (they go on across a reset()).
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

  /// Called with each frame's outcome on the SLAM thread, before counts() counts the frame.
  /// Set before start().
  void setFrameListener(std::function<void(const FrameOutcome&)> listener) { listener_ = std::move(listener); }
  /// Called after each update of the maps while running, on the maps thread (never when
  /// dense.enabled is false or both dense.live_every_* are 0). Set before start().
  void setMapsListener(std::function<void(const LiveMapsUpdate&)> listener) { maps_listener_ = std::move(listener); }
  /// Starts the System, the SLAM thread and the maps thread.
  void start();
  /// Hands a frame to the SLAM thread. False once stopped (the frame is not used).
  bool push(RgbdFrame frame);
  /// Writes the run outputs (trajectory so far, keyframes, sparse map, stats, config,
  /// map.plmap) into `dir` between two frames; the dense products are left to the end
  /// (they read the whole map without its lock: `plslam export` makes them from map.plmap).
  /// Throws what the writing throws.
  void save(const std::string& dir, const Json& stats_extra = nullptr);
  /// Drops the map (a loaded one too) between two frames: the current System finishes and
  /// a new one, mapping, with the same camera and options, takes the next frame as its first.
  /// The map frame is fixed anew, the maps while running start again, and every later output
  /// (save(), writeOutputs()) holds the new map and the poses tracked since. Throws Error
  /// before start() or after stop().
  void reset();
  /// Between two frames: track in the current map without changing it (no keyframes, no
  /// new landmarks; System::setLocalizationOnly), or map again. As `--localize` with a
  /// saved map does from the start; reset() goes back to mapping.
  void setLocalization(bool on);
  bool localizing() const { return localizing_; }
  SparseMapSnapshot sparseMap() const { return sparseMapSnapshot(currentSystem()->map()); }
  /// The fixed map frame of the outputs; empty until it is fixed.
  std::optional<MapFrame> mapFrame() const;
  SessionCounts counts() const;
  /// Ends the stream: the waiting frames are tracked, then the System finishes. Rethrows a
  /// failure of the SLAM thread. Calling it again does nothing.
  void stop();
  /// After stop(): the run outputs and, when `dense` and the options allow, the dense products,
  /// in the session's map frame (fixed now if it was not yet).
  void writeOutputs(const std::string& dir, const Json& stats_extra, bool dense);

  /// The current System (a new one after each reset(): do not keep the reference across one).
  const System& system() const { return *currentSystem(); }
  /// The maps while running (null when off).
  const LiveMaps* liveMaps() const { return maps_.get(); }

 private:
  void slamLoop();
  /// A new System on the session's camera and options, with its maps while running (not started).
  void makeSystem(Map map, const MapFrame* given);
  std::shared_ptr<System> currentSystem() const;
  /// Starts the System and its live maps (with the maps listener): at start() and after a reset.
  void startPipeline();
  /// Fixes the map frame from the map points when it is not fixed yet. Call between frames
  /// (feed_mutex_ held). Returns it.
  MapFrame fixMapFrame();
  /// Fills `out` from one fed frame; the revised trajectory after a loop correction.
  void describe(const RgbdFrame& frame, const TrackingResult& r, FrameOutcome* out);

  PinholeCamera camera_;
  SystemOptions options_;
  SessionOptions session_options_;
  // Replaced by reset() under feed_mutex_ and system_mutex_; readers on other threads
  // (sparseMap) hold a copy of the pointer, so that a System they read outlives a reset.
  std::shared_ptr<System> system_;
  mutable std::mutex system_mutex_;
  std::unique_ptr<LiveMaps> maps_;        // stopped before its System goes
  std::function<void(const LiveMapsUpdate&)> maps_listener_;
  std::string config_yaml_;
  BoundedQueue<RgbdFrame> queue_;
  std::function<void(const FrameOutcome&)> listener_;
  std::thread thread_;
  std::mutex feed_mutex_;  // held while a frame is fed, so save() sees the System between frames
  std::exception_ptr failure_;
  std::atomic<int> received_{0}, processed_{0}, tracked_{0};
  int keyframes_ = 0;      // in the current System
  int resets_ = 0;
  std::atomic<bool> localizing_{false};
  int map_frame_keyframes_;
  mutable std::mutex frame_mutex_;
  std::optional<MapFrame> map_frame_;  // under frame_mutex_
  uint64_t corrections_seen_ = 0;  // SLAM thread: Map::corrections() when the last outcome was made
  bool started_ = false, stopped_ = false;
};

}  // namespace plslam
