// The dense products of a growing map (dense/incremental_maps.h): new keyframes are folded
// in, a loop correction re-fuses from the corrected poses, and the map frame settles on the
// floor. Keyframe clouds of the rendered static scene at ground-truth poses (dense_scene.h).
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>

#include "dense/dense_products.h"
#include "dense/incremental_maps.h"
#include "dense_scene.h"

using namespace plslam;

namespace {

test::GtMap staticScene() {
  test::GtMapOptions o;
  o.frames = 120;
  o.every = 10;
  o.first_camera_world = true;
  return test::buildGtMap(o);
}

// Keyframe `kf` of `from` added to `to`, as the tracker and mapping thread would.
void addKeyframe(Map* to, const KeyFrame& kf) {
  KeyFrame copy;
  copy.t_ns = kf.t_ns;
  copy.T_w_c = kf.T_w_c;
  copy.dense = kf.dense;
  to->addKeyFrame(std::move(copy));
}

// The largest distance between the points of two clouds of the same voxels in the same order.
double maxPointDistance(const std::vector<FusedPoint>& a, const std::vector<FusedPoint>& b) {
  double d = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, double((a[i].p_w - b[i].p_w).norm()));
  return d;
}

Eigen::Vector3d centroid(const std::vector<FusedPoint>& cloud) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const FusedPoint& p : cloud) c += p.p_w.cast<double>();
  return cloud.empty() ? c : Eigen::Vector3d(c / cloud.size());
}

}  // namespace

TEST(IncrementalDenseMaps, GrowWithNewKeyframesAndEndAsTheFinalFusion) {
  const test::GtMap g = staticScene();
  const std::vector<const KeyFrame*> keyframes = [&] {
    std::vector<const KeyFrame*> v;
    for (const auto& [id, kf] : g.map.keyframes()) v.push_back(&kf);
    return v;
  }();
  ASSERT_GE(keyframes.size(), 9u);
  DenseOptions o;
  IncrementalDenseMaps maps(g.scene.camera(), o);
  Map growing;
  size_t last_points = 0, last_occupied = 0;
  int updates = 0;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    addKeyframe(&growing, *keyframes[i]);
    if (i % 3 != 2) continue;
    const IncrementalUpdate u = maps.update(growing);
    ASSERT_TRUE(u.changed);
    EXPECT_EQ(u.keyframes_added, 3);
    EXPECT_EQ(u.keyframes, static_cast<int>(i + 1));
    const DenseProducts& p = maps.products();
    const size_t occupied = summarizeOctree(*p.octree).occupied_leaves;
    EXPECT_GT(p.cloud.size(), last_points) << "update " << updates;
    EXPECT_GE(occupied, last_occupied) << "update " << updates;
    EXPECT_GT(p.grid.count(OccupancyGrid::kOccupied), 0);
    last_points = p.cloud.size(), last_occupied = occupied;
    ++updates;
  }
  // Nothing new: nothing done.
  EXPECT_FALSE(maps.update(growing).changed);
  // The floor of the static scene is found: the frame settles, as the end would find it.
  const std::optional<MapFrame> settled = maps.settledFrame();
  ASSERT_TRUE(settled.has_value());
  EXPECT_EQ(settled->floor_method, "ransac");
  const DenseProducts final_products = buildDenseProducts(growing, g.scene.camera(), o, {}, {}, &*settled);
  ASSERT_EQ(maps.products().cloud.size(), final_products.cloud.size());
  EXPECT_LT(maxPointDistance(maps.products().cloud, final_products.cloud), 1e-5);
}

TEST(IncrementalDenseMaps, LoopCorrectionRefusesWithTheCorrectedPoses) {
  const test::GtMap g = staticScene();
  Map map;
  for (const auto& [id, kf] : g.map.keyframes()) addKeyframe(&map, kf);
  DenseOptions o;
  MapFrame frame;  // given: the test is about the poses, not the floor
  frame.T_map_world = SE3(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())), Eigen::Vector3d(0, 0, 1));
  IncrementalDenseMaps maps(g.scene.camera(), o, &frame);
  ASSERT_TRUE(maps.update(map).changed);
  const Eigen::Vector3d before = centroid(maps.products().cloud);

  // A loop correction moves the second half of the keyframes by 0.3 m.
  const SE3 shift(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.3, 0, 0));
  std::vector<Id> ids;
  for (const auto& [id, kf] : map.keyframes()) ids.push_back(id);
  for (size_t i = ids.size() / 2; i < ids.size(); ++i) map.keyframe(ids[i])->T_w_c = shift * map.keyframe(ids[i])->T_w_c;
  // Without a correction counted, the products stay where they were (incremental only).
  EXPECT_FALSE(maps.update(map).changed);
  map.noteCorrection();
  const IncrementalUpdate u = maps.update(map);
  ASSERT_TRUE(u.changed);
  EXPECT_TRUE(u.refused);
  EXPECT_EQ(u.why, "loop correction");
  EXPECT_EQ(u.keyframes_added, 0);
  // The re-fused cloud is the fusion of the corrected poses, and it moved.
  const DenseProducts fresh = buildDenseProducts(map, g.scene.camera(), o, {}, {}, &frame);
  ASSERT_EQ(maps.products().cloud.size(), fresh.cloud.size());
  EXPECT_LT(maxPointDistance(maps.products().cloud, fresh.cloud), 1e-5);
  EXPECT_GT((centroid(maps.products().cloud) - before).norm(), 0.05);
  // So did the octree: every occupied voxel of the fresh one is occupied in the live one.
  const auto& live_tree = *maps.products().octree;
  int checked = 0, agree = 0;
  for (auto it = fresh.octree->begin_leafs(), end = fresh.octree->end_leafs(); it != end; ++it) {
    if (!fresh.octree->isNodeOccupied(*it)) continue;
    ++checked;
    const octomap::OcTreeNode* n = live_tree.search(it.getCoordinate());
    agree += n && live_tree.isNodeOccupied(n);
  }
  ASSERT_GT(checked, 100);
  EXPECT_EQ(agree, checked);
}
