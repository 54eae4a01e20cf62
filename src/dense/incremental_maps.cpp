#include "dense/incremental_maps.h"

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <chrono>

#include "dense/floor_plane.h"
#include "dense/octree_maps.h"
#include "dense/voxel_grid.h"

namespace plslam {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs f and records its wall time as a cost step (no peak memory: the high-water mark is
// the process's, and tracking runs meanwhile).
template <typename F>
void timedStep(DenseProducts* p, const char* step, F f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  DenseCost c;
  c.step = step;
  c.seconds = secondsSince(t0);
  p->costs.push_back(c);
}

// Whether two map frames differ by less than half an octree voxel and half a degree.
bool closeFrames(const SE3& a, const SE3& b, const DenseOptions& o) {
  const SE3 d = a * b.inverse();
  const double angle_deg = Eigen::AngleAxisd(d.rotation()).angle() * 180.0 / M_PI;
  return d.translation().norm() < 0.5 * o.octree_resolution_m && angle_deg < 0.5;
}

}  // namespace

/// What update() copies from the map under its lock.
struct IncrementalDenseMaps::Snapshot {
  std::map<Id, SE3> poses;                              ///< every keyframe with a dense cloud
  std::map<Id, std::vector<DensePoint>> new_clouds;     ///< of them, those not folded in yet
  SE3 T_w_c0;                                           ///< the first keyframe's pose (the floor search's start)
  uint64_t corrections = 0;
  int keyframes = 0;
};

IncrementalDenseMaps::IncrementalDenseMaps(const PinholeCamera& camera, const DenseOptions& options,
                                           const MapFrame* given)
    : camera_(camera), options_(options) {
  validateDenseOptions(options_);
  if (given) {
    given_ = *given;
    frame_settled_ = true;
  }
}

IncrementalDenseMaps::~IncrementalDenseMaps() = default;

std::optional<MapFrame> IncrementalDenseMaps::settledFrame() const {
  if (!frame_settled_ || updates_ == 0) return given_;
  return products_.frame;
}

IncrementalDenseMaps::Snapshot IncrementalDenseMaps::snapshot(const Map& map) const {
  Snapshot s;
  std::lock_guard<std::mutex> lock(map.mutex());
  s.corrections = map.corrections();
  s.keyframes = static_cast<int>(map.keyframes().size());
  if (!map.keyframes().empty()) s.T_w_c0 = map.keyframes().begin()->second.T_w_c;
  for (const auto& [id, kf] : map.keyframes()) {
    // A keyframe the mapping thread has not reached yet has no cloud: it comes next time.
    if (kf.dense.empty()) continue;
    s.poses[id] = kf.T_w_c;
    if (!clouds_.count(id)) s.new_clouds[id] = kf.dense;
  }
  return s;
}

void IncrementalDenseMaps::accumulate(const std::vector<DensePoint>& cloud_c, const SE3& T_w_c) {
  const Eigen::Matrix3f R = T_w_c.rotation().cast<float>();
  const Eigen::Vector3f t = T_w_c.translation().cast<float>();
  for (const DensePoint& d : cloud_c) {
    const Eigen::Vector3f p = R * d.p_c + t;
    if (voxels_) voxels_->add(p, d.r, d.g, d.b, d.class_id);
    else raw_w_.push_back({p, d.r, d.g, d.b, d.class_id, 1});
  }
}

// The fused cloud from every keyframe at its current pose, in id order as fuseCloud().
void IncrementalDenseMaps::fuseAll(const Snapshot& s) {
  raw_w_.clear();
  voxels_.reset();
  if (options_.fused_voxel_m > 0) voxels_ = std::make_unique<dense_detail::VoxelAccumulator>(options_.fused_voxel_m);
  for (const auto& [id, cloud] : clouds_) accumulate(cloud, s.poses.at(id));
}

MapFrame IncrementalDenseMaps::chooseFrame(const Snapshot& s, const std::vector<FusedPoint>& cloud_w,
                                           FloorPlane* floor, bool* moved) {
  *moved = updates_ == 0;
  if (given_) return *given_;
  if (frame_settled_) return products_.frame;
  // As estimateMapFrame(), from the copied first pose (the map is not locked here).
  *floor = estimateFloor(cloud_w, s.T_w_c0, camera_.imageUp(), options_);
  MapFrame f;
  f.T_map_world = floor->T_w_grid.inverse();
  f.floor_method = floor->method;
  f.floor_source = "dense";
  f.floor_points = floor->inliers;
  frame_settled_ = floor->method == "ransac";
  // A provisional frame that moved less than half a voxel and half a degree is kept, so
  // the octree is not rebuilt for the floor height's small changes as the cloud grows.
  if (updates_ > 0 && !frame_settled_ && closeFrames(f.T_map_world, products_.frame.T_map_world, options_))
    return products_.frame;
  *moved = true;
  return f;
}

IncrementalUpdate IncrementalDenseMaps::update(const Map& map) {
  const auto t0 = std::chrono::steady_clock::now();
  Snapshot s = snapshot(map);
  IncrementalUpdate u;
  const bool corrected = updates_ > 0 && s.corrections != corrections_;
  if (s.new_clouds.empty() && !corrected) return u;
  products_.costs.clear();
  u.changed = true;
  u.keyframes_added = static_cast<int>(s.new_clouds.size());
  u.corrections = s.corrections;
  u.why = updates_ == 0 ? "first" : corrected ? "loop correction" : "new keyframes";
  std::vector<FusedPoint> cloud_w;
  timedStep(&products_, "cloud", [&] { cloud_w = foldClouds(&s, corrected || updates_ == 0); });
  FloorPlane floor;
  MapFrame frame;
  bool new_frame = false;  // the octree is then rebuilt in the new frame
  timedStep(&products_, "map frame", [&] { frame = chooseFrame(s, cloud_w, &floor, &new_frame); });
  timedStep(&products_, "octomap", [&] { updateOctree(s, frame.T_map_world, corrected || new_frame); });
  u.refused = corrected || (new_frame && updates_ > 0);
  if (!corrected && u.refused) u.why = "map frame";
  products_.frame = frame;
  if (new_frame && !floor.method.empty()) products_.floor = floor;
  products_.keyframes = s.keyframes;
  products_.keyframes_with_cloud = static_cast<int>(clouds_.size());
  products_.keyframe_points = 0;
  for (const auto& [id, cloud] : clouds_) products_.keyframe_points += cloud.size();
  remakeDerived(std::move(cloud_w));
  corrections_ = s.corrections;
  ++updates_;
  u.keyframes = products_.keyframes_with_cloud;
  u.ms = secondsSince(t0) * 1000.0;
  return u;
}

// Adds the new keyframes' clouds to the voxels, or with `rebuild` every keyframe's at its
// current pose into new ones; returns the fused world cloud.
std::vector<FusedPoint> IncrementalDenseMaps::foldClouds(Snapshot* s, bool rebuild) {
  for (auto& [id, cloud] : s->new_clouds) clouds_[id] = std::move(cloud);
  if (rebuild) fuseAll(*s);
  else
    for (const auto& [id, cloud] : s->new_clouds) accumulate(clouds_.at(id), s->poses.at(id));
  if (!voxels_) return raw_w_;
  std::vector<FusedPoint> cloud_w;
  cloud_w.reserve(voxels_->size());
  voxels_->forEach(std::max(1, options_.min_voxel_points),
                   [&](const Eigen::Vector3f& c, uint8_t r, uint8_t g, uint8_t b, int16_t cls, int n) {
                     cloud_w.push_back({c, r, g, b, cls, n});
                   });
  return cloud_w;
}

// Inserts the new keyframes' scans, or with `rebuild` every keyframe's into a new tree.
void IncrementalDenseMaps::updateOctree(const Snapshot& s, const SE3& T_map_world, bool rebuild) {
  if (rebuild) products_.octree = makeOctree(options_);
  for (const auto& [id, pose] : s.poses)
    if (rebuild || s.new_clouds.count(id))
      insertKeyframeScan(products_.octree.get(), clouds_.at(id), T_map_world * pose, options_);
  products_.octree->updateInnerOccupancy();
  products_.octree->prune();
}

// The map-frame cloud, the semantic octree and the grid from the octree and the world cloud.
void IncrementalDenseMaps::remakeDerived(std::vector<FusedPoint> cloud_w) {
  const SE3& T = products_.frame.T_map_world;
  for (FusedPoint& q : cloud_w) q.p_w = (T * q.p_w.cast<double>()).cast<float>();
  products_.cloud = std::move(cloud_w);
  timedStep(&products_, "semantic octomap",
            [&] {
              SemanticOctrees trees = buildSemanticOctrees(*products_.octree, products_.cloud, options_);
              products_.semantic_octree = std::move(trees.colour);
              products_.label_octree = std::move(trees.labels);
            });
  // The tree is in the map frame, which is the grid's floor frame.
  timedStep(&products_, "grid", [&] { products_.grid = projectToGrid(*products_.octree, SE3(), T.inverse(), options_); });
}

}  // namespace plslam
