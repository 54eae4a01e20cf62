// Dense products of synthetic scenes at ground-truth poses: the cloud lies on the true
// surfaces, moving persons leave neither points nor occupied voxels, the camera's line of
// sight is free, and the 2D grid matches the walls and furniture.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "dense/dense_products.h"
#include "dense/floor_plane.h"
#include "dense/keyframe_cloud.h"
#include "dense/occupancy_grid.h"
#include "dense_scene.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

PinholeCamera smallCamera() {
  PinholeCamera c;
  c.width = 40;
  c.height = 30;
  c.fx = c.fy = 40;
  c.cx = 19.5;
  c.cy = 14.5;
  return c;
}

std::vector<Eigen::Vector3d> positions(const std::vector<FusedPoint>& cloud) {
  std::vector<Eigen::Vector3d> out;
  for (const FusedPoint& p : cloud) out.push_back(p.p_w.cast<double>());
  return out;
}

}  // namespace

TEST(KeyframeCloud, KeepsValidDepthInRangeAndLeavesOutMovingPixels) {
  const PinholeCamera cam = smallCamera();
  cv::Mat depth(cam.height, cam.width, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(0, 0, 10, 30)).setTo(std::nanf(""));   // no reading
  depth(cv::Rect(10, 0, 5, 30)).setTo(9.0f);            // beyond max_depth_m (and a depth jump at x = 15)
  cv::Mat bgr(cam.height, cam.width, CV_8UC3, cv::Scalar(10, 20, 30));
  cv::Mat mask(cam.height, cam.width, CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(30, 0, 10, 30)).setTo(0);               // a moving object
  cv::Mat classes(cam.height, cam.width, CV_16SC1, cv::Scalar(-1));
  classes(cv::Rect(20, 0, 5, 30)).setTo(56);            // a chair
  DenseOptions o;
  o.pixel_stride = 1;
  o.keyframe_voxel_m = 0;
  const std::vector<DensePoint> cloud = makeKeyframeCloud(cam, bgr, depth, mask, classes, o);
  // Columns 16..29 remain (15 borders the 9 m jump), 30 rows each.
  ASSERT_EQ(cloud.size(), 14u * 30u);
  int chair = 0;
  for (const DensePoint& p : cloud) {
    EXPECT_NEAR(p.p_c.z(), 2.0f, 1e-6);
    const double u = p.p_c.x() / p.p_c.z() * cam.fx + cam.cx;
    EXPECT_GE(u, 15.5);
    EXPECT_LT(u, 29.5);
    EXPECT_EQ(p.r, 30);
    EXPECT_EQ(p.b, 10);
    chair += p.class_id == 56;
    EXPECT_TRUE(p.class_id == 56 || p.class_id == -1);
  }
  EXPECT_EQ(chair, 5 * 30);
  // Downsampling: 1 m voxels at 2 m leave a handful of centroids, classes by majority.
  o.keyframe_voxel_m = 1.0;
  const std::vector<DensePoint> coarse = makeKeyframeCloud(cam, bgr, depth, mask, classes, o);
  EXPECT_GT(coarse.size(), 0u);
  EXPECT_LT(coarse.size(), 10u);
  // Wrong image types are refused.
  EXPECT_THROW(makeKeyframeCloud(cam, bgr, cv::Mat(cam.height, cam.width, CV_16UC1), mask, classes, o), DataError);
  EXPECT_THROW(makeKeyframeCloud(cam, bgr, depth, mask, cv::Mat(cam.height, cam.width, CV_16UC1), o), DataError);
}

TEST(DenseOptions, OutOfRangeValuesAreRefusedNamingTheKey) {
  DenseOptions o;
  o.floor = "sideways";
  try {
    validateDenseOptions(o);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dense.floor"), std::string::npos) << e.what();
  }
  o = DenseOptions();
  o.grid_max_height_m = o.grid_min_height_m;
  EXPECT_THROW(validateDenseOptions(o), ConfigError);
  for (int nice : {-1, 20}) {
    o = DenseOptions();
    o.live_nice = nice;
    try {
      validateDenseOptions(o);
      FAIL() << "live_nice " << nice << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("dense.live_nice"), std::string::npos) << e.what();
    }
  }
}

// map_server reads unknown cells (205) as occupancy 50/255: a free threshold from there up
// would make the planner drive through unexplored space, an occupied one below would wall it.
TEST(DenseOptions, GridThresholdsThatMapServerWouldReadUnknownCellsAcrossAreRefused) {
  EXPECT_NO_THROW(validateDenseOptions(DenseOptions())) << "map_server's own defaults 0.196 / 0.65";
  const struct {
    double free_thresh, occupied_thresh;
    const char* key;
  } bad[] = {{50.0 / 255, 0.65, "dense.grid_free_thresh"},
             {0.25, 0.65, "dense.grid_free_thresh"},
             {0.001, 0.65, "dense.grid_free_thresh"},
             {0.1, 0.19, "dense.grid_occupied_thresh"},
             {0.1, 1.0, "dense.grid_occupied_thresh"}};
  for (const auto& b : bad) {
    DenseOptions o;
    o.grid_free_thresh = b.free_thresh;
    o.grid_occupied_thresh = b.occupied_thresh;
    try {
      validateDenseOptions(o);
      ADD_FAILURE() << b.free_thresh << " / " << b.occupied_thresh << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(b.key), std::string::npos) << e.what();
    }
  }
  DenseOptions just_below;
  just_below.grid_free_thresh = 49.9 / 255;
  EXPECT_NO_THROW(validateDenseOptions(just_below));
}

TEST(GridYaml, ReadsMapServerYamlAndRefusesMalformedFilesNamingKeyAndLine) {
  const std::string good =
      "image: grid.pgm\nresolution: 0.05\norigin: [-1.5, 2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
      "free_thresh: 0.196\nmode: trinary\nunknown_key: ignored  # as map_server does\n";
  const GridYaml y = parseGridYaml(good, "grid.yaml");
  EXPECT_EQ(y.image, "grid.pgm");
  EXPECT_DOUBLE_EQ(y.origin.x(), -1.5);
  EXPECT_DOUBLE_EQ(y.free_thresh, 0.196);
  // The flow style map_server's own files use, and a block list, read the same.
  EXPECT_DOUBLE_EQ(parseGridYaml("{image: g.pgm, resolution: 0.1, origin: [0, 0, 0], negate: 1, occupied_thresh: 0.6, "
                                 "free_thresh: 0.2}", "flow.yaml").resolution, 0.1);
  const auto refused = [&](const std::string& from, const std::string& to, const std::string& needle) {
    std::string bad = good;
    bad.replace(bad.find(from), from.size(), to);
    try {
      parseGridYaml(bad, "grid.yaml");
      ADD_FAILURE() << "accepted:\n" << bad;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  refused("resolution: 0.05", "resolution: fine", "grid.yaml:2: resolution must be a number");
  refused("resolution: 0.05", "resolution: 0", "grid.yaml:2: resolution must be > 0");
  refused("origin: [-1.5, 2.0, 0.0]", "origin: [-1.5, 2.0]", "grid.yaml:3: origin must be a list of 3 numbers");
  refused("origin: [-1.5, 2.0, 0.0]", "origin: [-1.5, x, 0.0]", "grid.yaml:3: origin: 'x' is not a number");
  refused("negate: 0", "negate: 2", "grid.yaml:4: negate must be 0 or 1");
  refused("free_thresh: 0.196\n", "", "no 'free_thresh' key");
  refused("image: grid.pgm", "image: [grid.pgm", "grid.yaml:");
}

TEST(FloorPlane, StartsFromTheTopOfTheImageAlsoWhenFyIsNegative) {
  // A room seen from its first camera (the world frame): floor 1.2 m below, ceiling 1.3 m
  // above, a wall 4 m ahead. With fy > 0 the camera's y points down; the camera of the same
  // images with fy < 0 (ICL-NUIM's convention) has y up, so its cloud is the mirror in y.
  // Both must find the floor, not the ceiling, and a grid whose x is the camera's forward.
  PinholeCamera normal = smallCamera(), flipped = smallCamera();
  flipped.fy = -flipped.fy;
  flipped.cy = (flipped.height - 1) - flipped.cy;
  for (const PinholeCamera* cam : {&normal, &flipped}) {
    const double s = cam->fy > 0 ? 1.0 : -1.0;  // y of "down" in this camera's frame
    std::vector<FusedPoint> cloud;
    for (double a = -2; a <= 2; a += 0.1)
      for (double b = 0.5; b <= 4; b += 0.1) {
        FusedPoint f, c, w;
        f.p_w = Eigen::Vector3d(a, s * 1.2, b).cast<float>();
        c.p_w = Eigen::Vector3d(a, -s * 1.3, b).cast<float>();
        w.p_w = Eigen::Vector3d(a, s * (1.2 - 2.5 * (b - 0.5) / 3.5), 4.0).cast<float>();
        cloud.insert(cloud.end(), {f, c, w});
      }
    for (const char* method : {"ransac", "gravity"}) {
      SCOPED_TRACE(testing::Message() << "fy " << cam->fy << ", " << method);
      DenseOptions o;
      o.floor = method;
      const FloorPlane fl = estimateFloor(cloud, SE3(), cam->imageUp(), o);
      EXPECT_EQ(fl.method, method);
      EXPECT_GT(fl.up_w.dot(Eigen::Vector3d(0, -s, 0)), std::cos(1.0 * M_PI / 180)) << fl.up_w.transpose();
      EXPECT_NEAR(fl.height0, -1.2, 0.01) << "the floor is 1.2 m below the camera";
      EXPECT_NEAR(fl.height(Eigen::Vector3d(0, 0, 0)), 1.2, 0.01);
      const Eigen::Matrix3d R = fl.T_w_grid.rotation();
      EXPECT_GT(R.col(0).dot(Eigen::Vector3d::UnitZ()), 0.999) << "grid (map) x is the camera's forward";
      EXPECT_GT(R.col(2).dot(fl.up_w), 0.999);
    }
  }
}

// With a known mounting the robot stands on the floor: a large level plane 0.7 m above the
// base (a table top, or the loop scene's band of map points) is no floor, even where the real
// floor has too few points to be a candidate (the floor is then the base's own plane); where
// the floor is seen well enough, RANSAC's plane is kept. Without a mounting the table wins
// (nothing says where the floor is), which is what the mounting is for.
TEST(FloorPlane, WithAKnownMountingTheFloorIsWhereTheBaseStands) {
  const auto cloudOf = [](double floor_half_width) {
    std::vector<FusedPoint> cloud;  // the first camera's frame: y down
    for (double a = -2; a <= 2; a += 0.1)
      for (double b = 0.5; b <= 4; b += 0.1) {
        FusedPoint table;
        table.p_w = Eigen::Vector3d(a, 0.5, b).cast<float>();
        cloud.push_back(table);
        if (std::abs(a) <= floor_half_width && b >= 3.55) {
          FusedPoint floor;
          floor.p_w = Eigen::Vector3d(a, 1.2, b).cast<float>();
          cloud.push_back(floor);
        }
      }
    return cloud;
  };
  Eigen::Matrix3d R_b_c;  // optical z = base x, optical x = base -y, optical y = base -z
  R_b_c << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  DenseOptions mounted;
  mounted.T_base_cam = SE3(Eigen::Quaterniond(R_b_c), Eigen::Vector3d(0, 0, 1.2));  // camera 1.2 m above the base
  const Eigen::Vector3d image_up(0, -1, 0);

  const std::vector<FusedPoint> sparse_floor = cloudOf(0.15);  // 15 floor points: under floor_min_fraction
  const FloorPlane unmounted = estimateFloor(sparse_floor, SE3(), image_up, DenseOptions());
  EXPECT_EQ(unmounted.method, "ransac");
  EXPECT_NEAR(unmounted.height0, -0.5, 0.01) << "without a mounting the table top is taken";
  const FloorPlane on_base = estimateFloor(sparse_floor, SE3(), image_up, mounted);
  EXPECT_EQ(on_base.method, "base (no level plane at the base)");
  EXPECT_NEAR(on_base.height0, -1.2, 1e-9) << "the base's own plane";
  EXPECT_NEAR(on_base.height(Eigen::Vector3d::Zero()), 1.2, 1e-9);

  const std::vector<FusedPoint> seen_floor = cloudOf(2.0);  // the floor a candidate too
  const FloorPlane found = estimateFloor(seen_floor, SE3(), image_up, mounted);
  EXPECT_EQ(found.method, "ransac");
  EXPECT_NEAR(found.height0, -1.2, 0.01);
}

TEST(DenseMaps, FusedCloudLiesOnTheTrueSurfacesWithGroundTruthPoses) {
  test::GtMapOptions o;
  o.frames = 150;
  o.every = 20;
  o.width = 640;
  o.height = 480;
  const test::GtMap g = test::buildGtMap(o);
  const std::vector<FusedPoint> cloud = fuseCloud(g.map, o.dense);
  const double within_1cm = test::fractionOnStaticSurfaces(g.scene, cloud, 0.01);
  const double within_2cm = test::fractionOnStaticSurfaces(g.scene, cloud, 0.02);
  std::printf("static scene, ground-truth poses, depth noise on: %zu fused points, %.4f within 1 cm, %.4f within 2 cm\n",
              cloud.size(), within_1cm, within_2cm);
  EXPECT_GT(cloud.size(), 10000u);
  EXPECT_GE(within_1cm, 0.95);

  // Without the depth denoising the noise (sigma 0.002 z^2) shows.
  o.width = 320;
  o.height = 240;
  o.dense.smooth_radius_px = 0;
  const test::GtMap raw = test::buildGtMap(o);
  const double raw_1cm = test::fractionOnStaticSurfaces(raw.scene, fuseCloud(raw.map, o.dense), 0.01);
  o.noise = false;
  const test::GtMap exact = test::buildGtMap(o);
  const double exact_1cm = test::fractionOnStaticSurfaces(exact.scene, fuseCloud(exact.map, o.dense), 0.01);
  std::printf("within 1 cm: %.4f without denoising, %.4f with exact depth\n", raw_1cm, exact_1cm);
  EXPECT_LT(raw_1cm, within_1cm);
  EXPECT_GE(exact_1cm, 0.99);
}

TEST(DenseMaps, MovingPersonsLeaveNoPointsAndNoOccupiedVoxels) {
  test::GtMapOptions o;
  o.kind = synth::SceneKind::kDynamic;
  o.frames = 120;
  o.every = 8;
  o.dense.octree_resolution_m = 0.1;
  const test::GtMap on = test::buildGtMap(o);
  o.reject = false;
  const test::GtMap off = test::buildGtMap(o);
  const auto pointCount = [&](const test::GtMap& g) {
    return test::pointsOnMovingPath(g.scene, positions(fuseCloud(g.map, o.dense)), g.keyframe_times, 0.02, 0.05);
  };
  // A voxel centre is on the path when the person's surface is within half a voxel diagonal
  // of it and no static surface is that close.
  const double half_diag = 0.5 * std::sqrt(3.0) * o.dense.octree_resolution_m;
  const auto voxelCount = [&](const test::GtMap& g) {
    return test::pointsOnMovingPath(g.scene, test::occupiedVoxelCentres(*buildOctree(g.map, o.dense)), g.keyframe_times,
                                    half_diag, half_diag);
  };
  const int points_on = pointCount(on), points_off = pointCount(off);
  const int voxels_on = voxelCount(on), voxels_off = voxelCount(off);
  std::printf("dynamic scene, ground-truth poses: points on the persons' path %d with rejection, %d without; "
              "occupied voxels there %d with, %d without\n",
              points_on, points_off, voxels_on, voxels_off);
  EXPECT_GT(points_off, 100) << "persons must be in view for this test to mean anything";
  EXPECT_GT(voxels_off, 10);
  EXPECT_EQ(points_on, 0);
  EXPECT_EQ(voxels_on, 0);
}

TEST(DenseMaps, SpaceBetweenTheCameraAndTheSurfacesItSawIsFree) {
  test::GtMapOptions o;
  o.frames = 60;
  o.every = 10;
  o.dense.max_depth_m = 4.0;  // most walls of the room are 3 to 4 m away
  const test::GtMap g = test::buildGtMap(o);
  const auto tree = buildOctree(g.map, o.dense);
  const double res = o.dense.octree_resolution_m;
  int free = 0, occupied = 0, unknown = 0;
  // Rays through a grid of pixels of every keyframe: from 0.3 m to two voxels before the
  // surface the ray hits, every voxel must be free.
  for (const auto& [id, kf] : g.map.keyframes()) {
    const PinholeCamera& cam = g.scene.camera();
    for (int v = 10; v < cam.height; v += 20)
      for (int u = 10; u < cam.width; u += 20) {
        const Eigen::Vector3d dir = (kf.T_w_c.rotation() * cam.unprojectIdeal({double(u), double(v)}, 1.0)).normalized();
        const Eigen::Vector3d c = kf.T_w_c.translation();
        const synth::RayHit hit = g.scene.castRay(c, dir, kf.t_ns);
        if (!hit.hit || hit.distance > o.dense.max_depth_m) continue;
        for (double s = 0.3; s < hit.distance - 2 * res; s += res / 2) {
          const int state = voxelState(*tree, c + s * dir);
          free += state == 0;
          occupied += state == 1;
          unknown += state == -1;
        }
      }
  }
  const int all = free + occupied + unknown;
  std::printf("samples along the keyframes' lines of sight: %d free, %d occupied, %d unknown\n", free, occupied,
              unknown);
  ASSERT_GT(all, 1000);
  EXPECT_GE(free, 0.97 * all);
  EXPECT_LE(occupied, 0.01 * all);
}

TEST(DenseMaps, GridMatchesTheWallsAndFurnitureAndReadsBack) {
  test::GtMapOptions o;
  o.frames = 150;
  o.every = 10;
  o.dense.octree_resolution_m = 0.05;
  o.dense.grid_resolution_m = 0.05;
  const test::GtMap g = test::buildGtMap(o);
  DenseSelection what;
  const DenseProducts p = buildDenseProducts(g.map, g.scene.camera(), o.dense, what);
  // The synthetic world has z up and the floor at z = 0.
  std::printf("floor: %s, up (%.4f %.4f %.4f), height0 %.4f m; grid %dx%d: %d occupied, %d free, %d unknown\n",
              p.floor.method.c_str(), p.floor.up_w.x(), p.floor.up_w.y(), p.floor.up_w.z(), p.floor.height0,
              p.grid.width, p.grid.height, p.grid.count(OccupancyGrid::kOccupied), p.grid.count(OccupancyGrid::kFree),
              p.grid.count(OccupancyGrid::kUnknown));
  EXPECT_EQ(p.floor.method, "ransac");
  EXPECT_GT(p.floor.up_w.z(), std::cos(1.0 * M_PI / 180));
  EXPECT_NEAR(p.floor.height0, 0.0, 0.02);

  const synth::Scene& scene = g.scene;
  const double lo = o.dense.grid_min_height_m, hi = o.dense.grid_max_height_m, res = p.grid.resolution;
  // Truth per cell, from the column of points above its centre within the band.
  const auto obstacleNear = [&](int x, int y, double reach) {
    for (double h = lo; h <= hi; h += 0.02)
      if (scene.staticSurfaceDistance(p.grid.cellCentreWorld(x, y, h)) <= reach) return true;
    return false;
  };
  // A free cell is wrong when its centre column goes into a wall or a box by more than half
  // a cell (cells cut by a surface hold both sides).
  const auto blocked = [&](int x, int y) {
    const double depth = 0.5 * res + 0.005;
    for (double h = lo; h <= hi; h += 0.02) {
      const Eigen::Vector3d q = p.grid.cellCentreWorld(x, y, h);
      for (const synth::Box& b : scene.staticBoxes())
        if (b.signedDistance(q) < -depth) return true;
    }
    return false;
  };
  int occ = 0, occ_right = 0, fr = 0, fr_right = 0;
  for (int y = 0; y < p.grid.height; ++y)
    for (int x = 0; x < p.grid.width; ++x) {
      const int8_t c = p.grid.at(x, y);
      if (c == OccupancyGrid::kOccupied) {
        ++occ;
        occ_right += obstacleNear(x, y, 1.5 * res);
      } else if (c == OccupancyGrid::kFree) {
        ++fr;
        fr_right += !blocked(x, y);
      }
    }
  std::printf("grid vs scene: %d of %d occupied cells have a wall or box within 1.5 cells in the band, "
              "%d of %d free cells are open floor (not half a cell deep in a solid)\n", occ_right, occ, fr_right, fr);
  ASSERT_GT(occ, 100);
  ASSERT_GT(fr, 500);
  EXPECT_GE(occ_right, 0.95 * occ);
  EXPECT_GE(fr_right, 0.98 * fr);

  // The files read back: the same cells, resolution and origin.
  const std::string dir = test::scratchDir("dense_grid");
  DenseSelection grid_only;
  grid_only.pcd = grid_only.ply = grid_only.octomap = grid_only.semantic_octomap = false;
  const std::vector<WrittenFile> files = writeDenseProducts(dir, p, grid_only, o.dense);
  ASSERT_EQ(files.size(), 4u);  // map_frame.yaml, grid.pgm, grid.yaml, dense_products.json
  const OccupancyGrid back = readGrid(dir + "/grid.yaml");
  EXPECT_EQ(back.width, p.grid.width);
  EXPECT_EQ(back.height, p.grid.height);
  EXPECT_DOUBLE_EQ(back.resolution, p.grid.resolution);
  EXPECT_NEAR((back.origin - p.grid.origin).norm(), 0, 1e-6);
  EXPECT_EQ(back.cells, p.grid.cells);
  EXPECT_LT((back.T_w_grid.translation() - p.grid.T_w_grid.translation()).norm(), 1e-6);
  const GridYaml yaml = parseGridYaml(test::readFile(dir + "/grid.yaml"), "grid.yaml");
  EXPECT_EQ(yaml.image, "grid.pgm");
  EXPECT_EQ(yaml.mode, "trinary");
  EXPECT_EQ(yaml.negate, 0);
  EXPECT_DOUBLE_EQ(yaml.occupied_thresh, 0.65);
  EXPECT_DOUBLE_EQ(yaml.free_thresh, 0.196);
}
