// The module's OctoMap file: octree building, serialising and projecting.
#include "dense/octree_maps.h"

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <sstream>
#include <unordered_map>

#include "core/error.h"
#include "core/log.h"
#include "dense/label_octree.h"

namespace plslam {

namespace {

template <typename Tree>
void configure(Tree* tree, const DenseOptions& o) {
  tree->setProbHit(o.prob_hit);
  tree->setProbMiss(o.prob_miss);
  tree->setOccupancyThres(o.occupied_thresh);
}

// Inserts every keyframe's cloud as a scan from its camera centre; true when all were.
template <typename Tree>
bool insertKeyframes(Tree* tree, const Map& map, const DenseOptions& o, const char* stage,
                     const DenseProgress& progress, const SE3& T_out_w) {
  const size_t total = map.keyframes().size();
  size_t done = 0;
  for (const auto& [id, kf] : map.keyframes()) {
    insertKeyframeScan(tree, kf.dense, T_out_w * kf.T_w_c, o);
    if (progress && !progress(stage, ++done, total)) return false;
  }
  tree->updateInnerOccupancy();
  return true;
}

}  // namespace

template <typename Tree>
void insertKeyframeScan(Tree* tree, const std::vector<DensePoint>& cloud_c, const SE3& T_out_c, const DenseOptions& o) {
  if (cloud_c.empty()) return;
  const Eigen::Matrix3f R = T_out_c.rotation().cast<float>();
  const Eigen::Vector3f t = T_out_c.translation().cast<float>();
  octomap::Pointcloud scan;
  scan.reserve(cloud_c.size());
  for (const DensePoint& d : cloud_c) {
    const Eigen::Vector3f p = R * d.p_c + t;
    scan.push_back(p.x(), p.y(), p.z());
  }
  // discretize: one ray per end voxel, not per point (the clouds are denser than the tree).
  tree->insertPointCloud(scan, octomap::point3d(t.x(), t.y(), t.z()), o.max_range_m > 0 ? o.max_range_m : -1.0,
                         /*lazy_eval=*/true, /*discretize=*/true);
}
template void insertKeyframeScan(octomap::OcTree*, const std::vector<DensePoint>&, const SE3&, const DenseOptions&);

std::shared_ptr<octomap::OcTree> makeOctree(const DenseOptions& o) {
  auto tree = std::make_shared<octomap::OcTree>(o.octree_resolution_m);
  configure(tree.get(), o);
  return tree;
}

std::shared_ptr<octomap::OcTree> buildOctree(const Map& map, const DenseOptions& o, const DenseProgress& progress,
                                             bool* cancelled, const SE3& T_out_w) {
  auto tree = makeOctree(o);
  const bool complete = insertKeyframes(tree.get(), map, o, "octomap", progress, T_out_w);
  if (cancelled) *cancelled = !complete;
  tree->prune();
  return tree;
}

namespace {

// Copies the occupancy leaf by leaf (pruned leaves expanded): much cheaper than casting every
// keyframe's rays a second time.
template <typename Tree>
void copyOccupancy(const octomap::OcTree& occupancy, Tree* tree) {
  const double res = occupancy.getResolution();
  const unsigned max_depth = occupancy.getTreeDepth();
  for (auto it = occupancy.begin_leafs(), end = occupancy.end_leafs(); it != end; ++it) {
    const float log_odds = it->getLogOdds();
    if (it.getDepth() == max_depth) {
      tree->setNodeValue(it.getKey(), log_odds, /*lazy_eval=*/true);
      continue;
    }
    const int n = 1 << (max_depth - it.getDepth());
    const double size = it.getSize();
    const octomap::point3d c = it.getCoordinate();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const octomap::OcTreeKey key =
              tree->coordToKey(c.x() - size / 2 + (i + 0.5) * res, c.y() - size / 2 + (j + 0.5) * res,
                               c.z() - size / 2 + (k + 0.5) * res);
          tree->setNodeValue(key, log_odds, /*lazy_eval=*/true);
        }
  }
}

// The label of one voxel: the majority of its fused points ("no class" a candidate too).
struct VoxelLabel {
  octomap::OcTreeKey key;
  int16_t class_id = -1;
  uint32_t votes = 0, points = 0;
  Rgb colour;
};

// Votes per voxel: the most frequent class wins (a tie: the larger id); a voxel whose winner
// is "no class" gets the mean grey luminance of its unlabelled points. In first-touched
// order, so the trees are filled deterministically.
std::vector<VoxelLabel> voxelLabels(const octomap::OcTree& tree, const std::vector<FusedPoint>& fused) {
  struct Votes {
    std::vector<std::pair<int16_t, uint32_t>> classes;
    double luminance = 0;
    uint32_t unlabelled = 0, points = 0;
  };
  std::unordered_map<octomap::OcTreeKey, Votes, octomap::OcTreeKey::KeyHash> votes;
  std::vector<octomap::OcTreeKey> order;
  for (const FusedPoint& p : fused) {
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(p.p_w.x(), p.p_w.y(), p.p_w.z(), key)) continue;
    auto [it, inserted] = votes.try_emplace(key);
    if (inserted) order.push_back(key);
    Votes& v = it->second;
    const auto weight = static_cast<uint32_t>(std::max(1, p.points));
    v.points += weight;
    if (p.class_id < 0) {
      v.luminance += weight * semanticColour(p).r;
      v.unlabelled += weight;
    }
    bool found = false;
    for (auto& c : v.classes)
      if (c.first == p.class_id) c.second += weight, found = true;
    if (!found) v.classes.push_back({p.class_id, weight});
  }
  std::vector<VoxelLabel> labels;
  labels.reserve(order.size());
  for (const octomap::OcTreeKey& key : order) {
    const Votes& v = votes[key];
    VoxelLabel l;
    l.key = key;
    l.points = v.points;
    for (const auto& c : v.classes)
      if (c.second > l.votes || (c.second == l.votes && c.first > l.class_id)) l.class_id = c.first, l.votes = c.second;
    l.colour = classColour(l.class_id);
    if (l.class_id < 0 && v.unlabelled > 0) {
      const auto y = static_cast<uint8_t>(std::lround(v.luminance / v.unlabelled));
      l.colour = {y, y, y};
    }
    labels.push_back(l);
  }
  return labels;
}

template <typename Tree>
std::shared_ptr<Tree> occupancyCopy(const octomap::OcTree& occupancy, const DenseOptions& o) {
  auto tree = std::make_shared<Tree>(occupancy.getResolution());
  configure(tree.get(), o);
  copyOccupancy(occupancy, tree.get());
  tree->updateInnerOccupancy();
  return tree;
}

}  // namespace

SemanticOctrees buildSemanticOctrees(const octomap::OcTree& occupancy, const std::vector<FusedPoint>& fused,
                                     const DenseOptions& o) {
  const std::vector<VoxelLabel> labels = voxelLabels(occupancy, fused);
  SemanticOctrees out;
  out.colour = occupancyCopy<octomap::ColorOcTree>(occupancy, o);
  out.labels = occupancyCopy<LabelOcTree>(occupancy, o);
  // Only occupied voxels are labelled: a point in a voxel seen free is noise or was removed.
  for (const VoxelLabel& l : labels) {
    octomap::ColorOcTreeNode* c = out.colour->search(l.key);
    if (c && out.colour->isNodeOccupied(c)) c->setColor(l.colour.r, l.colour.g, l.colour.b);
    LabelOcTreeNode* n = out.labels->search(l.key);
    if (n && out.labels->isNodeOccupied(n)) n->setLabel(l.class_id, l.votes, l.points, l.colour.r, l.colour.g, l.colour.b);
  }
  out.colour->updateInnerOccupancy();
  out.colour->prune();
  out.labels->updateInnerOccupancy();
  out.labels->prune();
  return out;
}

std::string octreeToBt(const octomap::OcTree& tree) {
  std::ostringstream s;
  if (!tree.writeBinaryConst(s)) throw IoError("octomap: writing the binary tree failed");
  return s.str();
}

namespace {
std::string fullTreeFile(const octomap::AbstractOcTree& tree) {
  std::ostringstream s;
  if (!tree.write(s)) throw IoError("octomap: writing the " + tree.getTreeType() + " failed");
  return s.str();
}
}  // namespace

std::string octreeToOt(const octomap::ColorOcTree& tree) { return fullTreeFile(tree); }
std::string octreeToOt(const LabelOcTree& tree) { return fullTreeFile(tree); }

OccupancyGrid projectToGrid(const octomap::OcTree& tree, const SE3& T_tree_grid, const SE3& T_w_tree,
                            const DenseOptions& o) {
  const SE3 T_grid_tree = T_tree_grid.inverse();
  const Eigen::Matrix3d R = T_grid_tree.rotation();
  const Eigen::Vector3d t = T_grid_tree.translation();
  const double res = o.grid_resolution_m, hmin = o.grid_min_height_m, hmax = o.grid_max_height_m;
  const double sample = 0.5 * std::min(res, o.octree_resolution_m);

  // Cell (integer grid-frame coordinates) -> state; occupied wins over free.
  std::unordered_map<int64_t, int8_t> marks;
  // Shifted as unsigned: a left shift of a negative cx is undefined before C++20 (UBSan).
  const auto cellKey = [](int64_t cx, int64_t cy) {
    return static_cast<int64_t>((static_cast<uint64_t>(cx) << 32) ^ (static_cast<uint64_t>(cy) & 0xffffffffULL));
  };
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const double size = it.getSize();
    const bool occupied = tree.isNodeOccupied(*it);
    const octomap::point3d c = it.getCoordinate();
    const Eigen::Vector3d cg = R * Eigen::Vector3d(c.x(), c.y(), c.z()) + t;
    const double reach = 0.8661 * size;  // half the voxel's diagonal
    if (cg.z() + reach < hmin || cg.z() - reach > hmax) continue;
    const int n = std::max(1, static_cast<int>(std::ceil(size / sample - 1e-9)));
    const double step = size / n;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const Eigen::Vector3d off((i + 0.5) * step - 0.5 * size, (j + 0.5) * step - 0.5 * size,
                                    (k + 0.5) * step - 0.5 * size);
          const Eigen::Vector3d pg = cg + R * off;
          if (pg.z() < hmin || pg.z() > hmax) continue;
          const int64_t key = cellKey(static_cast<int64_t>(std::floor(pg.x() / res)),
                                      static_cast<int64_t>(std::floor(pg.y() / res)));
          if (occupied) marks[key] = OccupancyGrid::kOccupied;
          else marks.emplace(key, OccupancyGrid::kFree);
        }
  }

  OccupancyGrid g;
  g.resolution = res;
  g.T_w_grid = T_w_tree * T_tree_grid;
  if (marks.empty()) return g;
  int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
  for (const auto& [key, state] : marks) {
    const int64_t cx = key >> 32, cy = static_cast<int32_t>(key & 0xffffffff);
    x0 = std::min(x0, cx), x1 = std::max(x1, cx), y0 = std::min(y0, cy), y1 = std::max(y1, cy);
  }
  g.width = static_cast<int>(x1 - x0 + 1);
  g.height = static_cast<int>(y1 - y0 + 1);
  g.origin = Eigen::Vector2d(x0 * res, y0 * res);
  g.cells.assign(static_cast<size_t>(g.width) * g.height, OccupancyGrid::kUnknown);
  for (const auto& [key, state] : marks) {
    const int64_t cx = key >> 32, cy = static_cast<int32_t>(key & 0xffffffff);
    g.at(static_cast<int>(cx - x0), static_cast<int>(cy - y0)) = state;
  }
  return g;
}

OctreeSummary summarizeOctree(const octomap::OcTree& tree) {
  OctreeSummary s;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
    (tree.isNodeOccupied(*it) ? s.occupied_leaves : s.free_leaves)++;
  s.memory_bytes = tree.memoryUsage();
  return s;
}

int voxelState(const octomap::OcTree& tree, const Eigen::Vector3d& p) {
  const octomap::OcTreeNode* node = tree.search(p.x(), p.y(), p.z());
  if (!node) return -1;
  return tree.isNodeOccupied(node) ? 1 : 0;
}

}  // namespace plslam
