// The dense clouds the SLAM pipeline makes (mapping thread, dynamic masks of the run) on
// the rendered synthetic sequences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "camera/camera_file.h"
#include "core/option_table.h"
#include "dense/dense_products.h"
#include "dense_scene.h"
#include "io/dataset.h"
#include "support/test_support.h"
#include "synthetic_cache.h"
#include "system/system.h"

using namespace plslam;

namespace {

struct SlamRun {
  Map* map = nullptr;
  std::unique_ptr<System> slam;
  std::map<TimeNs, SE3> groundtruth;
};

SlamRun runSequence(synth::SceneKind kind, int frames, bool reject, const DenseOptions& dense) {
  const std::string dir = test::syntheticSequence(kind, frames);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  TumDataset data = TumDataset::open(dir, camera);
  SystemOptions options;
  options.sequential = true;
  options.dense = dense;
  options.dynamic.enabled = reject;
  options.dynamic.segment_every = 1;
  options.segmenter.kind = reject ? SegmenterKind::kReplay : SegmenterKind::kNone;
  for (const InstanceLabel& l : data.instanceLabels())
    options.segmenter.replay_labels.push_back({l.instance_id, l.class_id, l.class_name});
  SlamRun r;
  r.slam = std::make_unique<System>(camera, options);
  r.slam->start();
  RgbdFrame frame;
  while (data.next(&frame)) r.slam->feed(frame);
  r.slam->finish();
  for (const StampedPose& p : data.groundtruth()) r.groundtruth[p.t_ns] = p.T_w_c;
  return r;
}

// A copy of the run's keyframes (dense clouds) at their ground-truth poses, or at their
// SLAM poses carried into the scene frame through the first keyframe.
Map keyframesInSceneFrame(const SlamRun& r, bool slam_poses) {
  Map out;
  const auto& kfs = r.slam->map().keyframes();
  const KeyFrame& first = kfs.begin()->second;
  const SE3 T_scene_slam = r.groundtruth.at(first.t_ns) * first.T_w_c.inverse();
  for (const auto& [id, kf] : kfs) {
    KeyFrame k;
    k.t_ns = kf.t_ns;
    k.T_w_c = slam_poses ? T_scene_slam * kf.T_w_c : r.groundtruth.at(kf.t_ns);
    k.dense = kf.dense;
    out.addKeyFrame(std::move(k));
  }
  return out;
}

}  // namespace

TEST(DenseSlam, ConfigurationKeysReachTheDenseOptions) {
  SystemOptions o;
  OptionTable t;
  bindOptions(&t, &o);
  t.set("dense.fused_voxel_m", "0.03", "test");
  t.set("dense.floor", "gravity", "test");
  t.set("dense.enabled", "false", "test");
  EXPECT_DOUBLE_EQ(o.dense.fused_voxel_m, 0.03);
  EXPECT_EQ(o.dense.floor, "gravity");
  EXPECT_FALSE(o.dense.enabled);
  EXPECT_NE(t.toYaml().find("grid_max_height_m"), std::string::npos);
}

TEST(DenseSlam, StaticSceneCloudLiesOnTheSurfacesWithSlamAndGroundTruthPoses) {
  const SlamRun r = runSequence(synth::SceneKind::kStatic, 120, false, DenseOptions());
  size_t with_cloud = 0;
  for (const auto& [id, kf] : r.slam->map().keyframes()) with_cloud += !kf.dense.empty();
  EXPECT_EQ(with_cloud, r.slam->map().keyframes().size()) << "every keyframe gets its cloud";
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kStatic, [] {
    synth::SceneOptions s;
    s.frames = 120;
    return s;
  }());
  const DenseOptions o;
  const std::vector<FusedPoint> gt = fuseCloud(keyframesInSceneFrame(r, false), o);
  const std::vector<FusedPoint> est = fuseCloud(keyframesInSceneFrame(r, true), o);
  const double f_gt = test::fractionOnStaticSurfaces(scene, gt, 0.01);
  const double f_est = test::fractionOnStaticSurfaces(scene, est, 0.01);
  std::printf("static scene (120 frames, %zu keyframes): fraction of dense points within 1 cm of a surface: "
              "%.4f with ground-truth poses (%zu points), %.4f with SLAM poses (%zu points)\n",
              r.slam->map().keyframes().size(), f_gt, gt.size(), f_est, est.size());
  EXPECT_GE(f_gt, 0.95);
  EXPECT_GE(f_est, 0.90);
}

TEST(DenseSlam, PipelineMasksKeepWalkingPersonsOutOfTheClouds) {
  DenseOptions o;
  o.octree_resolution_m = 0.1;
  // (DenseMaps.MovingPersonsLeaveNoPointsAndNoOccupiedVoxels counts the same without rejection.)
  const SlamRun on = runSequence(synth::SceneKind::kDynamic, 120, true, o);
  synth::SceneOptions so;
  so.frames = 120;
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, so);
  const auto count = [&](const SlamRun& r, int* voxels) {
    const Map m = keyframesInSceneFrame(r, false);
    std::vector<TimeNs> times;
    for (const auto& [id, kf] : m.keyframes()) times.push_back(kf.t_ns);
    std::vector<Eigen::Vector3d> pts;
    for (const FusedPoint& p : fuseCloud(m, o)) pts.push_back(p.p_w.cast<double>());
    const double half_diag = 0.5 * std::sqrt(3.0) * o.octree_resolution_m;
    *voxels = test::pointsOnMovingPath(scene, test::occupiedVoxelCentres(*buildOctree(m, o)), times, half_diag,
                                       half_diag);
    return test::pointsOnMovingPath(scene, pts, times, 0.02, 0.05);
  };
  int voxels_on = 0;
  const int points_on = count(on, &voxels_on);
  // The persons were in view and masked: keyframes hold them as dynamic instances.
  int dynamic_instances = 0;
  for (const auto& [id, kf] : on.slam->map().keyframes())
    for (const KeyframeInstance& in : kf.instances) dynamic_instances += in.dynamic;
  std::printf("dynamic scene through the pipeline (replayed masks): dense points on the persons' path %d, occupied "
              "voxels there %d (%d dynamic instances in the keyframes)\n",
              points_on, voxels_on, dynamic_instances);
  EXPECT_GT(dynamic_instances, 0);
  EXPECT_EQ(points_on, 0);
  EXPECT_EQ(voxels_on, 0);
}
