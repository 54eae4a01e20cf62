// The dense products of a map that is still growing, kept up to date by small steps, for
// maps while a run goes on (session/live_maps.h runs it on its own thread).
//
// Each update() folds in what changed in the map since the last one:
//   - new keyframes (those whose dense cloud the mapping thread has stored): their clouds
//     are added to the fused cloud and inserted into the occupancy octree as scans, at the
//     poses they have now; earlier keyframes are not moved (local BA's small changes wait
//     for the end, whose products are built from the final poses);
//   - a loop correction (Map::corrections() changed): the cloud and the octree are
//     re-fused from every keyframe at its corrected pose;
//   - the map frame (core/map_frame.h): until a floor plane is found (FloorPlane method
//     "ransac") it is re-estimated at each update from the fused cloud, as the end of a run
//     does; when it moved by half an octree voxel or half a degree or more, the octree is
//     rebuilt in the new one (otherwise the previous frame is kept). Once a floor is found
//     (or when a saved map's frame is given) the frame stays, and the final products of
//     the run use it too (settledFrame()).
// The semantic octree and the 2D grid are then made again from the whole octree (cheaper
// than keeping them: both are linear in the octree's leaves).
//
// The fused cloud is accumulated in the SLAM world frame with the same voxels as
// fuseCloud(), then moved into the map frame, like buildDenseProducts() does.
//
// Thread safety: one thread calls update() and reads products(); the map may be changed by
// others meanwhile: update() holds map.mutex() only to copy the poses and the new clouds.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "core/map_frame.h"
#include "dense/dense_options.h"
#include "dense/dense_products.h"

namespace plslam {

namespace dense_detail {
class VoxelAccumulator;
}

/// What one update did.
struct IncrementalUpdate {
  bool changed = false;        ///< false: nothing new in the map, products unchanged
  int keyframes_added = 0;     ///< keyframes folded in by this update
  int keyframes = 0;           ///< keyframes in the products
  bool refused = false;        ///< rebuilt from every keyframe's current pose: the cloud and octree after a
                               ///< loop correction, the octree after a move of the provisional map frame
  std::string why;             ///< "first", "new keyframes", "loop correction", "map frame"
  uint64_t corrections = 0;    ///< Map::corrections() the products reflect
  double ms = 0;               ///< wall time of the update (copy, fusion, octrees, grid)
};

class IncrementalDenseMaps {
 public:
  /// `camera`: the map's (the floor search starts from its image's up). `given`: a map frame
  /// to use from the start (a saved map's); null: estimated as above. Throws ConfigError
  /// for bad options.
  IncrementalDenseMaps(const PinholeCamera& camera, const DenseOptions& options, const MapFrame* given = nullptr);
  ~IncrementalDenseMaps();
  IncrementalDenseMaps(const IncrementalDenseMaps&) = delete;
  IncrementalDenseMaps& operator=(const IncrementalDenseMaps&) = delete;

  /// Folds in what is new in `map` (see above) and remakes the products.
  IncrementalUpdate update(const Map& map);
  /// Every product (frame, cloud, octree, semantic octree, grid; costs of the last update),
  /// as buildDenseProducts() makes them; valid until the next update().
  const DenseProducts& products() const { return products_; }
  /// The map frame once it is final (given, or a floor plane found); nullopt before.
  std::optional<MapFrame> settledFrame() const;

 private:
  struct Snapshot;
  Snapshot snapshot(const Map& map) const;
  void accumulate(const std::vector<DensePoint>& cloud_c, const SE3& T_w_c);
  void fuseAll(const Snapshot& s);
  std::vector<FusedPoint> foldClouds(Snapshot* s, bool rebuild);
  MapFrame chooseFrame(const Snapshot& s, const std::vector<FusedPoint>& cloud_w, FloorPlane* floor, bool* moved);
  void updateOctree(const Snapshot& s, const SE3& T_map_world, bool rebuild);
  void remakeDerived(std::vector<FusedPoint> cloud_w);

  PinholeCamera camera_;
  DenseOptions options_;
  std::optional<MapFrame> given_;
  bool frame_settled_ = false;
  std::map<Id, std::vector<DensePoint>> clouds_;  ///< own copies of the keyframes' camera-frame clouds (never change)
  std::unique_ptr<dense_detail::VoxelAccumulator> voxels_;  ///< fused cloud, world frame (fused_voxel_m > 0)
  std::vector<FusedPoint> raw_w_;                 ///< the unfused cloud, world frame (fused_voxel_m = 0)
  uint64_t corrections_ = 0;
  int updates_ = 0;
  DenseProducts products_;
};

}  // namespace plslam
