// Maps while a run goes on: the dense products (fused cloud, OctoMaps, 2D grid) of a
// growing map, updated on their own thread every dense.live_every_keyframes keyframes or
// dense.live_every_s seconds (dense/dense_options.h), written into the output folder as
// the end of the run writes them (dense/dense_products.h, each file atomically) and handed
// to a listener (the ROS node publishes them). Used by plslam run, plslam live and
// LiveSession (the ROS node).
//
// The thread is woken by the System's keyframe observer (attach()), which only counts,
// so tracking and mapping never wait for a map update; the update itself takes the map's
// lock only to copy poses and new clouds (dense/incremental_maps.h). The thread runs at
// dense.live_nice (lowest priority by default).
//
// Frame: every product is in the map frame of core/map_frame.h. Until a floor plane is
// found it is re-estimated at each update (products may then shift between updates, and
// map_frame.yaml says which floor method gave it); once found, it is kept, and
// settledFrame() hands it to the end of the run so that the final products are in the
// same frame as the live ones.
//
// A failed update (a file that cannot be written, say) is logged and the next one tried:
// maps are a by-product and never stop tracking.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/json.h"
#include "dense/dense_products.h"
#include "dense/incremental_maps.h"
#include "system/system.h"

namespace plslam {

/// One update as a listener sees it: shared, immutable products (map frame).
struct LiveMapsUpdate {
  int index = 0;                 ///< 1 for the first update
  IncrementalUpdate what;        ///< keyframes added, re-fusion, time
  MapFrame frame;                ///< the products' frame
  bool frame_settled = false;    ///< false: provisional (no floor plane yet)
  std::shared_ptr<const std::vector<FusedPoint>> cloud;  ///< fused cloud, map frame (set only when a listener is)
  std::shared_ptr<const OccupancyGrid> grid;             ///< 2D grid (width 0: none yet)
  double write_ms = 0;           ///< writing the files (0: no folder)
};

/// The updates of a session, for stats.json.
struct LiveMapsStats {
  int updates = 0, refusions = 0, failures = 0;
  std::vector<double> update_ms;  ///< per update: incremental update (fusion, octrees, grid)
  std::vector<double> write_ms;   ///< per update: writing the files
};
/// The stats as JSON members: live_map_updates, live_map_refusions, live_map_failures,
/// live_map_update_ms and live_map_write_ms (median, max).
Json liveMapsStatsJson(const LiveMapsStats& stats);

class LiveMaps {
 public:
  /// `map` and `camera`: the System's (it must outlive this). `out_dir`: where the files
  /// go (empty: none written, the listener only). `given`: a saved map's frame (may be null).
  LiveMaps(const Map& map, const PinholeCamera& camera, const DenseOptions& options, std::string out_dir,
           const MapFrame* given = nullptr);
  ~LiveMaps();
  LiveMaps(const LiveMaps&) = delete;
  LiveMaps& operator=(const LiveMaps&) = delete;

  /// Called after each update on the maps thread. Set before start().
  void setListener(std::function<void(const LiveMapsUpdate&)> listener) { listener_ = std::move(listener); }
  /// Makes `system`'s keyframe observer wake this (before system->start()).
  void attach(System* system);
  void start();
  /// A keyframe was mapped: counts it, wakes the thread when an update is due. Cheap,
  /// thread-safe, harmless after stop().
  void keyframeMapped();
  /// Ends the thread after the update in progress (no further update: the end of the run
  /// builds the final products) and frees the maps' memory (their own copies of the
  /// keyframe clouds, the voxels, the octrees). Calling it again does nothing.
  void stop();

  /// The map frame once final (given, or a floor found); nullopt before.
  std::optional<MapFrame> settledFrame() const;
  LiveMapsStats stats() const;

 private:
  void loop();
  bool due();  // under signal_->mutex
  void runUpdate();

  const Map& map_;
  std::unique_ptr<IncrementalDenseMaps> maps_;  // released by stop(): the end's products need the memory
  DenseOptions options_;
  std::string out_dir_;
  std::function<void(const LiveMapsUpdate&)> listener_;
  std::thread thread_;
  /// What the keyframe observer touches (shared with it), and the lock of the stats.
  struct Signal {
    std::mutex mutex;
    std::condition_variable wake;
    int pending = 0;        ///< keyframes mapped since the last update
    bool stopping = false;
    void keyframeMapped();
  };
  std::shared_ptr<Signal> signal_ = std::make_shared<Signal>();
  uint64_t corrections_ = 0;   // Map::corrections() of the last update
  std::chrono::steady_clock::time_point last_update_;
  bool started_ = false;
  LiveMapsStats stats_;
  std::optional<MapFrame> settled_;
};

/// LiveMaps for `system` (its map, camera and dense options),
/// attached to its keyframe observer, not started; null when the options turn them off
/// (dense.enabled false, or both dense.live_every_* 0). Before system->start().
std::unique_ptr<LiveMaps> makeLiveMaps(System* system, std::string out_dir, const MapFrame* given = nullptr);

}  // namespace plslam
