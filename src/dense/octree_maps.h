// OctoMaps of a map's dense clouds and the 2D grid projected from them.
//
//   octomap.bt            octomap::OcTree, binary (writeBinary: occupied / free / unknown),
//                         pruned; every keyframe's cloud inserted as a scan from its camera
//                         centre (insertPointCloud, rays cut at max_range_m), so space the
//                         camera looked through is free and surfaces are occupied.
//   octomap_semantic.ot   octomap::ColorOcTree (write: full log-odds and colours), the same
//                         occupancy; each occupied voxel coloured with the semantic colour of
//                         the fused points in it (dense/cloud_fusion.h: palette colour of the
//                         most frequent class, grey luminance for points without class).
//                         Readable by octovis and every OctoMap tool.
//   octomap_labels.ot     plslam::LabelOcTree (dense/label_octree.h: write), the same
//                         occupancy; each occupied voxel with its class id, the votes for it,
//                         the points in it and the same colour. The class is the majority of
//                         the fused points in the voxel (the rule of the colours above).
//                         Read back with octomap::AbstractOcTree::read in a program linking
//                         plslam_dense; octovis cannot create the type (it says "Cannot open
//                         OcTree file"), hence the colour tree beside it.
// Moving objects are not in the keyframe clouds (dynamic pixels are left out), so they
// leave no occupied voxels.
//
// The octomap types are only declared here: include <octomap/OcTree.h> /
// <octomap/ColorOcTree.h> / "dense/label_octree.h" to use the trees (plslam_dense links octomap).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/map.h"
#include "dense/cloud_fusion.h"
#include "dense/dense_options.h"
#include "core/se3.h"
#include "dense/occupancy_grid.h"

namespace octomap {
class OcTree;
class ColorOcTree;
}  // namespace octomap

namespace plslam {

class LabelOcTree;

/// The occupancy octree of every keyframe's cloud (final poses). Same caller duty as
/// fuseCloud(); `cancelled` (may be null) is set when progress stopped it (tree partial).
/// The tree is built in the frame `out` of T_out_w (the map frame: T_map_world), so that
/// its voxels are aligned with the floor; the world frame by default.
std::shared_ptr<octomap::OcTree> buildOctree(const Map& map, const DenseOptions& options,
                                             const DenseProgress& progress = {}, bool* cancelled = nullptr,
                                             const SE3& T_out_w = SE3());
/// An empty occupancy octree with the options' resolution and probabilities.
std::shared_ptr<octomap::OcTree> makeOctree(const DenseOptions& options);
/// Inserts one keyframe's camera-frame cloud as a scan from its camera centre (the
/// keyframe's pose in the tree's frame: T_out_c), rays cut at max_range_m, lazily: call
/// tree->updateInnerOccupancy() after a batch. Instantiated for octomap::OcTree. Nothing for
/// an empty cloud.
template <typename Tree>
void insertKeyframeScan(Tree* tree, const std::vector<DensePoint>& cloud_c, const SE3& T_out_c,
                        const DenseOptions& options);

/// The two semantic trees of one occupancy (see above).
struct SemanticOctrees {
  std::shared_ptr<octomap::ColorOcTree> colour;  ///< octomap_semantic.ot
  std::shared_ptr<LabelOcTree> labels;           ///< octomap_labels.ot
};
/// The occupancy of `occupancy` copied into both trees, occupied voxels labelled and
/// coloured from the fused points `fused` (same frame as the tree) falling in them.
SemanticOctrees buildSemanticOctrees(const octomap::OcTree& occupancy, const std::vector<FusedPoint>& fused,
                                     const DenseOptions& options);

/// File contents: OcTree::writeBinary (.bt) and AbstractOcTree::write (.ot: the tree type
/// in the header, full node data).
std::string octreeToBt(const octomap::OcTree& tree);
std::string octreeToOt(const octomap::ColorOcTree& tree);
std::string octreeToOt(const LabelOcTree& tree);

/// The 2D grid in the floor frame `grid` (z up, origin on the floor; T_tree_grid: its pose
/// in the tree's frame, identity when the tree was built in the map frame) between
/// grid_min_height_m and grid_max_height_m above the floor: a cell is occupied when any
/// occupied voxel of that band lies over it, free when voxels of the band over it were seen
/// free and none occupied, unknown otherwise. Voxels are sampled at half the cell size so
/// that none falls between cells of a tilted floor frame. The grid's T_w_grid is
/// T_w_tree * T_tree_grid (T_w_tree: the tree's frame in the SLAM world).
OccupancyGrid projectToGrid(const octomap::OcTree& tree, const SE3& T_tree_grid, const SE3& T_w_tree,
                            const DenseOptions& options);

/// What an octree holds, for summaries.
struct OctreeSummary {
  size_t occupied_leaves = 0, free_leaves = 0;
  size_t memory_bytes = 0;  ///< octomap's own estimate (memoryUsage())
};
OctreeSummary summarizeOctree(const octomap::OcTree& tree);

/// The state of the voxel holding world point p: -1 unknown, 0 free, 1 occupied.
int voxelState(const octomap::OcTree& tree, const Eigen::Vector3d& p_w);

}  // namespace plslam
