// The map frame (core/map_frame.h) of the dense products on the synthetic static scene,
// its world being the first camera's frame as in a SLAM run: the written octomap.bt read
// back with OctoMap has its floor at z = 0 and vertical walls, the cloud lies on the true
// surfaces through the true map frame, map_frame.yaml agrees with the truth.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <cstdio>

#include "core/map_frame.h"
#include "dense/dense_products.h"
#include "dense_scene.h"
#include "system/run_outputs.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

void printCheck(const char* what, const test::MapFrameCheck& k) {
  std::printf("%s: rotation error %.3f deg (up %.3f deg), first camera %.4f m above the floor (true %.4f); "
              "%d floor voxels: mean z %+.4f m, 95%% within %.4f m; %zu vertical faces, largest tilt %.3f deg\n",
              what, k.rotation_error_deg, k.up_error_deg, k.camera_height_m, k.true_camera_height_m, k.floor_voxels,
              k.floor_mean_z, k.floor_p95_abs_z, k.faces.size(), k.max_wall_tilt_deg);
}

}  // namespace

TEST(MapFrame, WrittenOctomapHasTheFloorAtZeroAndVerticalWalls) {
  test::GtMapOptions o;
  o.frames = 150;
  o.every = 10;
  o.first_camera_world = true;
  // The camera is 3.5-4 m from the shelf's wall: see it.
  o.dense.max_depth_m = 4.5;
  o.dense.max_range_m = 5.0;
  const test::GtMap g = test::buildGtMap(o);
  ASSERT_GT(g.T_scene_world.angle(), 0.5) << "the first camera must be tilted and turned for this test to mean anything";
  const DenseProducts p = buildDenseProducts(g.map, g.scene.camera(), o.dense);
  ASSERT_FALSE(p.cancelled);
  EXPECT_EQ(p.frame.floor_method, "ransac");
  EXPECT_EQ(p.frame.floor_source, "dense");
  const std::string dir = test::scratchDir("map_frame_octomap");
  writeDenseProducts(dir, p, {}, o.dense);

  // What a user gets: the .bt read by OctoMap, the frame from map_frame.yaml.
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir + "/" + kOctomapBt));
  const double res = tree.getResolution();
  EXPECT_DOUBLE_EQ(res, o.dense.octree_resolution_m);
  const MapFrame frame = parseMapFrameYaml(test::readFile(dir + "/" + kMapFrameYaml), kMapFrameYaml);
  EXPECT_LT((frame.T_map_world.inverse() * p.frame.T_map_world).angle(), 1e-6);
  EXPECT_LT((frame.T_map_world.translation() - p.frame.T_map_world.translation()).norm(), 1e-6);

  const test::MapFrameCheck k = test::checkMapFrame(g.scene, g.T_scene_world, frame.T_map_world, tree);
  printCheck("static scene, ground-truth poses in the first camera's frame", k);
  EXPECT_LT(k.rotation_error_deg, 0.5);
  EXPECT_LT(k.up_error_deg, 0.3);
  EXPECT_NEAR(k.camera_height_m, k.true_camera_height_m, 0.01);
  ASSERT_GT(k.floor_voxels, 200);
  EXPECT_LT(std::abs(k.floor_mean_z), res) << "the floor is at z = 0 within a voxel";
  EXPECT_LT(k.floor_p95_abs_z, 2 * res);
  ASSERT_GE(k.faces.size(), 1u);
  std::printf("faces: %s\n", k.facesText().c_str());
  EXPECT_LT(k.max_wall_tilt_deg, 2.0) << "walls are vertical";

  // The cloud is in the same frame: through the true map frame it lies on the scene's surfaces.
  const SE3 T_scene_map = test::trueMapFrame(g.T_scene_world);
  std::vector<FusedPoint> in_scene = p.cloud;
  for (FusedPoint& q : in_scene) q.p_w = (T_scene_map * q.p_w.cast<double>()).cast<float>();
  const double on = test::fractionOnStaticSurfaces(g.scene, in_scene, 0.02);
  std::printf("cloud: %.4f of %zu points within 2 cm of a surface through the true map frame\n", on, in_scene.size());
  EXPECT_GE(on, 0.95);
}

TEST(MapFrame, GivenFrameIsUsedAndTheGridIsInIt) {
  test::GtMapOptions o;
  o.frames = 60;
  o.every = 15;
  o.first_camera_world = true;
  const test::GtMap g = test::buildGtMap(o);
  const DenseProducts found = buildDenseProducts(g.map, g.scene.camera(), o.dense);
  MapFrame given = found.frame;
  given.T_map_world = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 5)) * found.frame.T_map_world;
  given.floor_method = "test";
  const DenseProducts p = buildDenseProducts(g.map, g.scene.camera(), o.dense, {}, {}, &given);
  EXPECT_EQ(p.frame.floor_method, "test");
  EXPECT_TRUE(p.floor.method.empty()) << "no floor search with a given frame";
  ASSERT_EQ(p.cloud.size(), found.cloud.size());
  for (size_t i = 0; i < p.cloud.size(); i += 97) EXPECT_NEAR(p.cloud[i].p_w.z() - found.cloud[i].p_w.z(), 5.0, 1e-4);
  // The grid's frame is the map frame: its T_w_grid is T_map_world^-1.
  ASSERT_GT(found.grid.width, 0);
  EXPECT_LT((found.grid.T_w_grid * found.frame.T_map_world).angle(), 1e-9);
  EXPECT_LT((found.grid.T_w_grid * found.frame.T_map_world).translation().norm(), 1e-9);
}

// A known mounting (calibration.camera_to_base): the map frame's origin is on the floor
// below the base at the first keyframe and x its forward direction, so the base poses
// (trajectory_base.txt: T_map_base = T_map_world * T_w_c * T_base_cam^-1) are the true
// base poses relative to the first base's footprint. The true base here stands level on the
// floor 0.25 m behind and 0.05 m right of the camera's footprint, turned 20 deg left of the
// camera's heading (the camera looks 20 deg to the right of forward): its x differs from the
// camera's optical axis laid on the floor, so a frame anchored to the camera fails this test.
TEST(MapFrame, KnownMountingPutsTheOriginBelowTheBaseAndMovesTheBaseTrajectoryAsTrue) {
  test::GtMapOptions o;
  o.frames = 90;
  o.every = 10;
  o.first_camera_world = true;
  const test::GtMap g = test::buildGtMap(o);
  const SE3 T_scene_c0 = g.T_scene_world;
  const SE3 T_scene_footprint_c = test::trueMapFrame(T_scene_c0);  // below the camera, x its heading
  const double yaw = 20.0 * M_PI / 180.0;
  const SE3 T_scene_b0 = T_scene_footprint_c * SE3(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
                                                   Eigen::Vector3d(-0.25, -0.05, 0.0));
  const SE3 T_base_cam = T_scene_b0.inverse() * T_scene_c0;
  DenseOptions dense = o.dense;
  dense.T_base_cam = T_base_cam;
  const DenseProducts p = buildDenseProducts(g.map, g.scene.camera(), dense);
  EXPECT_EQ(p.frame.origin, "base");
  EXPECT_EQ(p.frame.floor_method, "ransac");

  // The map frame is the first base's pose: T_map_world = T_scene_b0^-1 * T_scene_world.
  const SE3 T_map_world_true = T_scene_b0.inverse() * g.T_scene_world;
  const SE3 error = p.frame.T_map_world * T_map_world_true.inverse();
  std::printf("known mounting: map frame error %.4f deg, %.4f m\n", error.angle() * 180 / M_PI,
              error.translation().norm());
  EXPECT_LT(error.angle() * 180 / M_PI, 0.3);
  EXPECT_LT((p.frame.T_map_world.translation() - T_map_world_true.translation()).norm(), 0.01);

  // The base trajectory of the keyframes against the true base poses.
  Trajectory camera;
  for (const auto& [id, kf] : g.map.keyframes()) camera.push_back({kf.t_ns, kf.T_w_c});
  const Trajectory base = baseTrajectory(camera, p.frame.T_map_world, T_base_cam);
  ASSERT_EQ(base.size(), camera.size());
  ASSERT_GE(base.size(), 5u);
  double worst_m = 0, worst_deg = 0;
  for (size_t i = 0; i < base.size(); ++i) {
    const SE3 T_scene_c = g.T_scene_world * camera[i].T_w_c;
    const SE3 truth = T_scene_b0.inverse() * T_scene_c * T_base_cam.inverse();
    worst_m = std::max(worst_m, (base[i].T_w_c.translation() - truth.translation()).norm());
    worst_deg = std::max(worst_deg, (base[i].T_w_c.inverse() * truth).angle() * 180 / M_PI);
  }
  std::printf("known mounting: %zu base poses, worst error %.4f m, %.4f deg\n", base.size(), worst_m, worst_deg);
  EXPECT_LT(worst_m, 0.02);
  EXPECT_LT(worst_deg, 0.3);
  // At the first keyframe the base is at the origin, facing x.
  EXPECT_LT(base.front().T_w_c.translation().norm(), 0.01);
  EXPECT_LT(base.front().T_w_c.angle() * 180 / M_PI, 0.3);
}
