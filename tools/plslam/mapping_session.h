// What plslam run and plslam live share between their frame sources and their summaries:
// a System (from a saved map or empty) with its maps while running, started and stopped
// together, then the dense products and the run outputs written in one map frame.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "camera/pinhole_camera.h"
#include "core/json.h"
#include "core/map_frame.h"
#include "session/live_maps.h"
#include "session/run_config.h"
#include "system/system.h"

namespace plslam::cli {

class MappingSession {
 public:
  /// `config->map` (when given) is moved into the System and its map frame kept for every
  /// output. `dense`: maps while running into `out` and the dense products at the end.
  MappingSession(const PinholeCamera& camera, RunConfig* config, std::string out, bool dense);
  MappingSession(const MappingSession&) = delete;
  MappingSession& operator=(const MappingSession&) = delete;

  System& slam() { return slam_; }
  void start();
  /// Stops the maps while running, then the System (every queued keyframe mapped).
  void stop();
  /// After stop(): the dense products (when on and the map has keyframes) and the run
  /// outputs, in the saved map's frame, else the one the maps while running settled on,
  /// else the dense cloud's floor. `stats_extra` gets the live maps' figures. `save_map`
  /// empty: <out>/map.plmap. False when Ctrl-C stopped the dense products.
  bool writeOutputs(Json stats_extra, const std::string& save_map, bool progress);

 private:
  PinholeCamera camera_;
  const RunConfig* config_;
  std::string out_;
  bool dense_;
  std::optional<MapFrame> frame_;
  System slam_;
  std::unique_ptr<LiveMaps> maps_;
};

}  // namespace plslam::cli
