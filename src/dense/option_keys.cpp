// The configuration keys of the dense products (dense.): one line per field; the doc string
// is the field's documentation.
#include "core/option_table.h"
#include "dense/dense_options.h"

namespace plslam {

void bindDenseOptions(OptionTable* t, DenseOptions* o) {
  DenseOptions& dn = *o;
  t->bind("dense.enabled", &dn.enabled, "make a dense cloud per keyframe (needed for plslam run/export dense products)");
  t->bind("dense.min_depth_m", &dn.min_depth_m, "pixels nearer than this are left out of the clouds (m)");
  t->bind("dense.max_depth_m", &dn.max_depth_m, "pixels farther than this are left out of the clouds (m)");
  t->bind("dense.pixel_stride", &dn.pixel_stride, "use every n-th pixel in u and v");
  t->bind("dense.edge_jump_ratio", &dn.edge_jump_ratio, "drop flying pixels: depth differing from a 4-neighbour's by more than this fraction of it (0 = keep)");
  t->bind("dense.smooth_radius_px", &dn.smooth_radius_px, "depth denoising: inverse depth averaged over a (2r+1)^2 window of similar depths, r in px (0 = off)");
  t->bind("dense.depth_sigma_coeff", &dn.depth_sigma_coeff, "depth noise sigma = coeff * z^2, gates the denoising window (1/m)");
  t->bind("dense.keyframe_voxel_m", &dn.keyframe_voxel_m, "voxel size of each keyframe's cloud (m, 0 = none)");
  t->bind("dense.fused_voxel_m", &dn.fused_voxel_m, "voxel size of the fused world cloud (m, 0 = keep every point)");
  t->bind("dense.min_voxel_points", &dn.min_voxel_points, "fused voxels with fewer points are dropped");
  t->bind("dense.octree_resolution_m", &dn.octree_resolution_m, "OctoMap leaf size (m)");
  t->bind("dense.max_range_m", &dn.max_range_m, "OctoMap rays are cut at this range; farther points only mark free space (m, <= 0: none)");
  t->bind("dense.prob_hit", &dn.prob_hit, "OctoMap occupancy probability of a ray end");
  t->bind("dense.prob_miss", &dn.prob_miss, "OctoMap occupancy probability along a ray");
  t->bind("dense.occupied_thresh", &dn.occupied_thresh, "OctoMap voxels above this probability are occupied");
  t->bind("dense.floor", &dn.floor, "floor plane for the grid: ransac (lowest level plane) or gravity (the first camera's image up)");
  t->bind("dense.floor_max_tilt_deg", &dn.floor_max_tilt_deg, "ransac floor: max angle to the first camera's up (deg)");
  t->bind("dense.floor_inlier_m", &dn.floor_inlier_m, "ransac floor: inlier distance (m)");
  t->bind("dense.floor_search_fraction", &dn.floor_search_fraction,
          "ransac floor: searched among this lowest fraction of the points along the prior up (1: all)");
  t->bind("dense.floor_min_fraction", &dn.floor_min_fraction, "ransac floor: fraction of the searched points a floor needs");
  t->bind("dense.floor_max_above_base_m", &dn.floor_max_above_base_m,
          "ransac floor with calibration.camera_to_base: a level plane higher than this above the base's origin is no "
          "floor (the robot stands on it); none left: the base's own plane (m)");
  t->bind("dense.grid_min_height_m", &dn.grid_min_height_m, "2D grid: lower end of the obstacle band above the floor (m)");
  t->bind("dense.grid_max_height_m", &dn.grid_max_height_m, "2D grid: upper end of the obstacle band above the floor (m)");
  t->bind("dense.grid_resolution_m", &dn.grid_resolution_m, "2D grid cell size (m)");
  t->bind("dense.grid_occupied_thresh", &dn.grid_occupied_thresh, "map YAML occupied_thresh");
  t->bind("dense.grid_free_thresh", &dn.grid_free_thresh, "map YAML free_thresh");
  t->bind("dense.live_every_keyframes", &dn.live_every_keyframes,
          "maps while running: update the dense products after this many new keyframes (0 = not by count)");
  t->bind("dense.live_every_s", &dn.live_every_s,
          "maps while running: update this many seconds after the last update when something is new "
          "(0 = not by time; both 0 = only at the end)");
  t->bind("dense.live_nice", &dn.live_nice, "maps while running: nice value of their thread (0..19; 19 = idle cycles)");
}

}  // namespace plslam
