// Options of the dense maps: the per-keyframe clouds the mapping thread makes, and the
// products built from them at the end of a run or by `plslam export` (fused cloud,
// OctoMaps, 2D occupancy grid), at the end of a run and while it runs. One struct; keys
// `dense.*` in a run configuration.
#pragma once

#include <optional>
#include <string>

#include "core/se3.h"

namespace plslam {

struct DenseOptions {
  // --- per keyframe (mapping thread) ---
  bool enabled = true;                ///< make a dense cloud for every keyframe
  double min_depth_m = 0.3;           ///< pixels nearer than this are left out (m)
  double max_depth_m = 3.0;           ///< pixels farther than this are left out (m; depth noise grows with z^2)
  int pixel_stride = 2;               ///< use every n-th pixel in u and v (1 = all)
  double edge_jump_ratio = 0.03;      ///< drop pixels whose depth differs from a 4-neighbour's by more than this fraction of it (flying pixels; 0 = keep)
  int smooth_radius_px = 2;           ///< depth denoising: average inverse depth over a (2r+1)^2 window of similar depths (0 = off)
  double depth_sigma_coeff = 0.002;   ///< depth noise sigma = coeff * z^2 (m, z in m; Kinect-like); window pixels within 3 sigma are averaged
  double keyframe_voxel_m = 0.01;     ///< voxel size of the per-keyframe downsampling, camera frame (m; 0 = none)

  // --- fused cloud (export) ---
  double fused_voxel_m = 0.01;        ///< voxel size of the fused world cloud (m; 0 = no fusion, every point kept)
  int min_voxel_points = 1;           ///< fused voxels with fewer points than this are dropped (outliers)

  // --- OctoMap (export) ---
  double octree_resolution_m = 0.05;  ///< leaf size of the octrees (m)
  double max_range_m = 4.0;           ///< rays are cut at this range; farther points only mark free space (m; <= 0: no limit)
  double prob_hit = 0.7;              ///< occupancy probability of a ray end point
  double prob_miss = 0.4;             ///< occupancy probability of a voxel a ray passes through
  double occupied_thresh = 0.5;       ///< a voxel is occupied above this probability

  // --- floor and 2D grid (export) ---
  std::string floor = "ransac";       ///< floor plane: "ransac" (lowest large plane near level) or "gravity" (up of the first keyframe's image: -y, +y when fy < 0)
  double floor_max_tilt_deg = 30.0;   ///< ransac: candidate planes within this angle of the first camera's up (its image's top)
  double floor_inlier_m = 0.02;       ///< ransac: inlier distance to a plane (m)
  double floor_search_fraction = 0.3; ///< ransac: the floor is searched among this lowest fraction of the points along the prior up (1: all)
  double floor_min_fraction = 0.05;   ///< ransac: a plane needs this fraction of the searched points to be a floor candidate
  double floor_max_above_base_m = 0.10;  ///< ransac with a camera-to-base transform: a plane higher than this above the base's origin at the first keyframe is no floor (the robot stands on the floor)
  double grid_min_height_m = 0.10;    ///< the grid's height band above the floor, lower end (m)
  double grid_max_height_m = 2.0;     ///< upper end (m): obstacles between the two block a robot
  double grid_resolution_m = 0.05;    ///< cell size of the 2D grid (m)
  double grid_occupied_thresh = 0.65; ///< written to the map YAML (map_server: occupied above)
  double grid_free_thresh = 0.196;    ///< written to the map YAML (map_server: free below)

  // --- the robot (not a key: loaded from calibration.camera_to_base by session/run_config) ---
  /// p_base = T_base_cam * p_camera. When set, the map frame's origin is on the floor below
  /// the base at the first keyframe, x its forward direction, and the floor search takes
  /// the base's z as its prior up (dense/floor_plane.h).
  std::optional<SE3> T_base_cam;
  // --- maps while running (plslam run, plslam live, the ROS node; session/live_maps.h) ---
  // An update is due once live_every_keyframes keyframes were mapped since the last one,
  // or live_every_s seconds after it when at least one keyframe (or a loop correction)
  // came meanwhile. Both 0: no maps before the end.
  int live_every_keyframes = 10;      ///< update after this many new keyframes (0 = not by count)
  double live_every_s = 5.0;          ///< update this long after the last one, if anything is new (s; 0 = not by time)
  // The maps are the least urgent work of a run: at the lowest priority they take the
  // cycles tracking and mapping leave, instead of a share of a two-core robot's CPU that
  // slows every frame as the map grows (docs/RESULTS.md, "Long run").
  int live_nice = 19;                 ///< nice value of the maps thread (0..19)

  bool liveMaps() const { return enabled && (live_every_keyframes > 0 || live_every_s > 0); }
};

/// Throws ConfigError naming the field when an option is out of range.
void validateDenseOptions(const DenseOptions& options);

}  // namespace plslam
