// The dense clouds the SLAM pipeline makes (mapping thread, dynamic masks of the run) on
// the rendered synthetic sequences.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "camera/camera_file.h"
#include "core/option_table.h"
#include "dense/dense_products.h"
#include "dense_scene.h"
#include "core/map_frame.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "mapfile/map_file.h"
#include "support/test_support.h"
#include "synthetic_cache.h"
#include "system/run_outputs.h"
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

// A SLAM run's outputs (octomap.bt, sparse_map.ply, trajectory_map.txt, map_frame.yaml,
// map.plmap) are all in one map frame, found from the floor of the SLAM cloud, that agrees
// with the scene's truth.
TEST(DenseSlam, RunOutputsAreInOneMapFrameThatMatchesTheTruth) {
  DenseOptions o;
  // The camera is 3.5-4 m from the shelf's wall: see it.
  o.max_depth_m = 4.5;
  o.max_range_m = 5.0;
  const SlamRun r = runSequence(synth::SceneKind::kStatic, 120, false, o);
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kStatic, [] {
    synth::SceneOptions s;
    s.frames = 120;
    return s;
  }());
  const KeyFrame& first = r.slam->map().keyframes().begin()->second;
  const SE3 T_scene_world = r.groundtruth.at(first.t_ns) * first.T_w_c.inverse();
  const DenseProducts p = buildDenseProducts(r.slam->map(), r.slam->camera(), o);
  const std::string dir = test::scratchDir("dense_slam_map_frame");
  writeDenseProducts(dir, p, {}, o);
  writeRunOutputs(dir, *r.slam, "", nullptr, "", &p.frame);

  const MapFrame frame = parseMapFrameYaml(test::readFile(dir + "/" + kMapFrameYaml), kMapFrameYaml);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir + "/" + kOctomapBt));
  const test::MapFrameCheck k = test::checkMapFrame(scene, T_scene_world, frame.T_map_world, tree);
  std::printf("static scene, SLAM (120 frames): map frame rotation error %.3f deg (up %.3f deg), first camera "
              "%.4f m above the floor (true %.4f); %d floor voxels: mean z %+.4f m, 95%% within %.4f m; %zu vertical faces, "
              "largest tilt %.3f deg\n", k.rotation_error_deg, k.up_error_deg, k.camera_height_m,
              k.true_camera_height_m, k.floor_voxels, k.floor_mean_z, k.floor_p95_abs_z, k.faces.size(), k.max_wall_tilt_deg);
  EXPECT_LT(k.up_error_deg, 1.0);
  EXPECT_NEAR(k.camera_height_m, k.true_camera_height_m, 0.03);
  ASSERT_GT(k.floor_voxels, 100);
  EXPECT_LT(std::abs(k.floor_mean_z), o.octree_resolution_m);
  EXPECT_LT(k.floor_p95_abs_z, 2 * o.octree_resolution_m);
  ASSERT_GE(k.faces.size(), 1u);
  std::printf("faces: %s\n", k.facesText().c_str());
  EXPECT_LT(k.max_wall_tilt_deg, 3.0);

  // The sparse map in the same frame: through the true map frame its points (grey vertices;
  // line endpoints may overshoot the surfaces) lie on the scene, read as world-frame points they do not.
  const SE3 T_scene_map = test::trueMapFrame(T_scene_world);
  const std::string ply = test::readFile(dir + "/sparse_map.ply");
  std::istringstream rows(ply.substr(ply.find("end_header\n") + 11));
  int on = 0, on_as_world = 0, points = 0;
  for (std::string row; std::getline(rows, row);) {
    if (row.find(" 160 160 160") == std::string::npos) continue;
    Eigen::Vector3d v;
    std::istringstream(row) >> v.x() >> v.y() >> v.z();
    ++points;
    on += scene.staticSurfaceDistance(T_scene_map * v) < 0.05;
    on_as_world += scene.staticSurfaceDistance(T_scene_world * v) < 0.05;
  }
  std::printf("sparse_map.ply: %d of %d map points within 5 cm of a surface through the true map frame "
              "(%d if they were in the SLAM world frame)\n", on, points, on_as_world);
  ASSERT_GT(points, 100);
  EXPECT_GE(on, 0.9 * points);

  // trajectory_map.txt = T_map_world * trajectory.txt; the map file keeps the frame.
  const Trajectory world = readTumTrajectory(dir + "/trajectory.txt");
  const Trajectory in_map = readTumTrajectory(dir + "/" + kTrajectoryMap);
  ASSERT_EQ(world.size(), in_map.size());
  for (size_t i = 0; i < world.size(); i += 10)
    EXPECT_LT(((frame.T_map_world * world[i].T_w_c).translation() - in_map[i].T_w_c.translation()).norm(), 1e-4);
  const LoadedMap loaded = loadMap(dir + "/map.plmap");
  ASSERT_TRUE(loaded.frame.has_value());
  EXPECT_LT((loaded.frame->T_map_world.translation() - frame.T_map_world.translation()).norm(), 1e-6);
}
