// The dense products of a map, built in one call and written in one call: what `plslam
// run` leaves at the end of a run and `plslam export` makes from a saved map.
//
// Every product is in the map frame (core/map_frame.h: z up, x forward, origin on the floor
// below the first camera), found from the floor of the fused cloud unless given.
// Files written by writeDenseProducts(dir, ...), each atomically (core/atomic_file.h):
//   map_frame.yaml             T_map_world and how it was found (core/map_frame.h)
//   dense_cloud.pcd            fused cloud, binary PCD PointXYZRGBL (dense/cloud_fusion.h)
//   dense_cloud_semantic.ply   fused cloud, semantic colours and classes (ditto)
//   octomap.bt                 occupancy octree (dense/octree_maps.h)
//   octomap_semantic.ot        colour octree with semantic colours (ditto)
//   octomap_labels.ot          the same with class ids per voxel (ditto; dense/label_octree.h)
//   grid.pgm, grid.yaml        2D occupancy grid, ROS map_server (dense/occupancy_grid.h)
//   dense_products.json        counts, floor, grid frame, time and peak memory per product,
//                              file sizes
//
// Thread safety: call after System::finish() or on a loaded map; nothing else may change
// the map meanwhile (nothing is locked).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "core/map_frame.h"
#include "dense/cloud_fusion.h"
#include "dense/dense_options.h"
#include "dense/floor_plane.h"
#include "dense/occupancy_grid.h"
#include "dense/octree_maps.h"

namespace plslam {

/// File names in the output folder.
inline constexpr char kDenseCloudPcd[] = "dense_cloud.pcd";
inline constexpr char kDenseCloudPly[] = "dense_cloud_semantic.ply";
inline constexpr char kOctomapBt[] = "octomap.bt";
inline constexpr char kOctomapSemanticOt[] = "octomap_semantic.ot";
inline constexpr char kOctomapLabelsOt[] = "octomap_labels.ot";
inline constexpr char kGridPgm[] = "grid.pgm";
inline constexpr char kGridYaml[] = "grid.yaml";
inline constexpr char kDenseSummaryJson[] = "dense_products.json";

/// Which products to build and write.
struct DenseSelection {
  bool pcd = true;               ///< dense_cloud.pcd
  bool ply = true;               ///< dense_cloud_semantic.ply
  bool octomap = true;           ///< octomap.bt
  bool semantic_octomap = true;  ///< octomap_semantic.ot and octomap_labels.ot
  bool grid = true;              ///< grid.pgm + grid.yaml
  bool any() const { return pcd || ply || octomap || semantic_octomap || grid; }
};

/// Time and peak memory of one step. The peak is the process's resident set high-water
/// mark during the step (reset before it where Linux allows: /proc/self/clear_refs),
/// so it includes what was already resident (the map).
struct DenseCost {
  std::string step;          ///< "cloud", "octomap", "semantic octomap", "floor", "grid", "write"
  double seconds = 0;
  double peak_rss_mb = 0;    ///< high-water mark during the step (0: not measurable here)
  double start_rss_mb = 0;   ///< resident set when the step began
};

struct DenseProducts {
  int keyframes = 0;                   ///< keyframes in the map
  int keyframes_with_cloud = 0;        ///< of them, with a dense cloud
  size_t keyframe_points = 0;          ///< points of all keyframe clouds
  MapFrame frame;                      ///< the frame of every product (given, or found from the floor)
  FloorPlane floor;                    ///< the floor found, SLAM world frame (method empty when the frame was given)
  std::vector<FusedPoint> cloud;       ///< fused cloud, map frame (built for pcd, ply, semantic octomap, grid)
  std::shared_ptr<octomap::OcTree> octree;                 ///< map frame; built for octomap and grid
  std::shared_ptr<octomap::ColorOcTree> semantic_octree;   ///< map frame; built for semantic_octomap
  std::shared_ptr<LabelOcTree> label_octree;               ///< map frame, class ids; built for semantic_octomap
  OccupancyGrid grid;                  ///< map frame (T_w_grid = T_map_world^-1); built for grid
  std::vector<DenseCost> costs;
  bool cancelled = false;              ///< progress stopped the build: products are incomplete
};

/// Builds the selected products (and what they need) from the keyframes' dense clouds and
/// final poses, in the map frame `given` (a saved map's), or, when null, in the one found
/// from the floor of the fused cloud (estimateMapFrame). `camera` is the map's camera (the
/// floor starts from the top of its image, PinholeCamera::imageUp()). `progress` (may be
/// empty) is called after each keyframe of each step; returning false stops the build
/// (cancelled). Throws ConfigError for bad options.
DenseProducts buildDenseProducts(const Map& map, const PinholeCamera& camera, const DenseOptions& options,
                                 const DenseSelection& what = {}, const DenseProgress& progress = {},
                                 const MapFrame* given = nullptr);

struct WrittenFile {
  std::string path;
  uintmax_t bytes = 0;
};
/// Writes the selected products that were built into `dir` (created if needed) and the
/// summary JSON; returns the files with their sizes. Throws IoError naming a file that
/// could not be written. Nothing is written for cancelled products.
std::vector<WrittenFile> writeDenseProducts(const std::string& dir, const DenseProducts& products,
                                            const DenseSelection& what, const DenseOptions& options);

/// The summary as JSON (what dense_products.json holds).
std::string denseSummaryJson(const DenseProducts& products, const DenseOptions& options,
                             const std::vector<WrittenFile>& files);

/// The process's resident set now and its high-water mark, MB (0 where /proc is absent).
double residentMb();
double peakResidentMb();
/// Resets the high-water mark to the current resident set; false where not allowed.
bool resetPeakResident();

}  // namespace plslam
