// Options of the dense maps: the per-keyframe clouds the mapping thread makes, and the
// products built from them at the end of a run or by `plslam export` (fused cloud,
// OctoMaps, 2D occupancy grid), at the end of a run and while it runs. One struct; keys
// `dense.*` in a run configuration.
#pragma once

#include <optional>
#include <string>

#include "core/se3.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindDenseOptions (dense/option_keys.cpp). `plslam run --print-config` lists them.
struct DenseOptions {
  // --- per keyframe (mapping thread) ---
  bool enabled = true;
  double min_depth_m = 0.3;
  double max_depth_m = 3.0;
  int pixel_stride = 2;
  double edge_jump_ratio = 0.03;
  int smooth_radius_px = 2;
  double depth_sigma_coeff = 0.002;
  double keyframe_voxel_m = 0.01;

  // --- fused cloud (export) ---
  double fused_voxel_m = 0.01;
  int min_voxel_points = 1;

  // --- OctoMap (export) ---
  double octree_resolution_m = 0.05;
  double max_range_m = 4.0;
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double occupied_thresh = 0.5;

  // --- floor and 2D grid (export) ---
  std::string floor = "ransac";
  double floor_max_tilt_deg = 30.0;
  double floor_inlier_m = 0.02;
  double floor_search_fraction = 0.3;
  double floor_min_fraction = 0.05;
  double floor_max_above_base_m = 0.10;
  double grid_min_height_m = 0.10;
  double grid_max_height_m = 2.0;
  double grid_resolution_m = 0.05;
  double grid_occupied_thresh = 0.65;
  double grid_free_thresh = 0.196;

  // --- the robot (not a key: loaded from calibration.camera_to_base by session/run_config) ---
  /// p_base = T_base_cam * p_camera. When set, the map frame's origin is on the floor below
  /// the base at the first keyframe, x its forward direction, and the floor search takes
  /// the base's z as its prior up (dense/floor_plane.h).
  std::optional<SE3> T_base_cam;
  // --- maps while running (plslam run, plslam live, the ROS node; session/live_maps.h) ---
  // An update is due once live_every_keyframes keyframes were mapped since the last one,
  // or live_every_s seconds after it when at least one keyframe (or a loop correction)
  // came meanwhile. Both 0: no maps before the end.
  int live_every_keyframes = 10;
  double live_every_s = 5.0;
  // The maps are the least urgent work of a run: at the lowest priority they take the
  // cycles tracking and mapping leave, instead of a share of a two-core robot's CPU that
  // slows every frame as the map grows (docs/RESULTS.md, "Long run").
  int live_nice = 19;

  bool liveMaps() const { return enabled && (live_every_keyframes > 0 || live_every_s > 0); }
};

/// Binds the dense.* keys (dense/option_keys.cpp).
void bindDenseOptions(OptionTable* table, DenseOptions* options);

/// Throws ConfigError naming the field when an option is out of range.
void validateDenseOptions(const DenseOptions& options);

}  // namespace plslam
