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
