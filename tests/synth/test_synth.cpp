// The synthetic scenes are the ground truth of the other modules' tests, so these check
// that images, depth, masks and poses agree with the scene geometry exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "camera/camera_file.h"
#include "core/error.h"
#include "io/trajectory_file.h"
#include "support/test_support.h"
#include "synth/dataset.h"
#include "synth/renderer.h"
#include "synth/scene.h"
#include "synth/texture.h"

namespace fs = std::filesystem;
using namespace plslam;
using namespace plslam::synth;

namespace {

SceneOptions exact(int frames = 300) {
  SceneOptions o;
  o.frames = frames;
  o.noise.enabled = false;
  return o;
}

Eigen::Vector3d backProject(const Scene& s, const RenderedFrame& f, int x, int y) {
  const double z = f.depth_m.at<float>(y, x);
  return f.T_w_c * s.camera().unprojectIdeal(Eigen::Vector2d(x, y), z);
}

/// The ray through pixel (x, y) of a frame, in the world.
Eigen::Vector3d rayDir(const Scene& s, const RenderedFrame& f, double x, double y) {
  const auto& c = s.camera();
  return f.T_w_c.quaternion() * Eigen::Vector3d((x - c.cx) / c.fx, (y - c.cy) / c.fy, 1.0);
}

/// Moving-object pixel counts per frame on a small render.
std::vector<int> coverage(SceneKind kind, int frames) {
  SceneOptions o = exact(frames);
  o.width = 160;
  o.height = 120;
  o.aa_samples = 1;
  const Scene s = makeScene(kind, o);
  std::vector<int> out;
  for (int i = 0; i < frames; ++i) out.push_back(cv::countNonZero(render(s, i).instance_ids));
  return out;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// "stamp file" lines of a TUM index file.
std::vector<std::pair<std::string, std::string>> readIndex(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::pair<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    std::string a, b;
    is >> a >> b;
    rows.push_back({a, b});
  }
  return rows;
}

}  // namespace

TEST(SynthScene, DepthPixelsBackProjectOntoTheSurfaceTheyCameFrom) {
  for (SceneKind kind : {SceneKind::kStatic, SceneKind::kDynamic}) {
    const Scene s = makeScene(kind, exact());
    const RenderedFrame f = render(s, 120);
    double worst = 0;
    int checked = 0;
    for (int y = 0; y < f.depth_m.rows; y += 2)
      for (int x = 0; x < f.depth_m.cols; x += 2) {
        ASSERT_TRUE(std::isfinite(f.depth_m.at<float>(y, x))) << "no depth without noise at " << x << "," << y;
        worst = std::max(worst, s.surfaceDistance(backProject(s, f, x, y), f.t_ns));
        ++checked;
      }
    EXPECT_LT(worst, 1e-6) << sceneKindName(kind) << ": " << checked << " pixels checked";
  }
}

TEST(SynthScene, VisibleBoxCornersProjectOntoPixelsWithTheirDepth) {
  // For each visible box corner, take the point 1 mm inside one of its visible faces,
  // turn the camera slightly so that this point projects exactly onto a pixel centre, and
  // require that pixel to hold the point's depth (a test of the projection convention to
  // well below a pixel, and of the depth).
  SceneOptions o = exact();
  o.width = 320;
  o.height = 240;
  const Scene s = makeScene(SceneKind::kStatic, o);
  const auto& cam = s.camera();
  int checked = 0;
  for (int frame : {0, 100, 200, 290}) {
    const SE3 T_w_c = s.cameraPose(frame);
    const TimeNs t = s.frameTime(frame);
    const Eigen::Vector3d centre = T_w_c.translation();
    int in_frame = 0;
    for (size_t bi = 1; bi < s.staticBoxes().size() && in_frame < 6; ++bi) {
      const Box& box = s.staticBoxes()[bi];
      const auto corners = box.corners();
      for (int ci = 0; ci < 8 && in_frame < 6; ++ci) {
        // The three edges from this corner, and the faces between pairs of them.
        Eigen::Vector3d e[3];
        for (int k = 0; k < 3; ++k) e[k] = (corners[ci ^ (1 << k)] - corners[ci]).normalized();
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d n = e[(k + 1) % 3].cross(e[(k + 2) % 3]);  // normal of the face spanned by two edges
          const Eigen::Vector3d outward = n.dot(e[k]) > 0 ? -n : n;
          if (outward.dot(corners[ci] - centre) >= -1e-3) continue;  // face not turned to the camera
          const Eigen::Vector3d target = corners[ci] + 1e-3 * (e[(k + 1) % 3] + e[(k + 2) % 3]);
          const Eigen::Vector3d p_c = T_w_c.inverse() * target;
          if (p_c.z() < 0.3) continue;
          const Eigen::Vector2d uv = cam.projectIdeal(p_c);
          if (!cam.inImage(uv, 3)) continue;
          const RayHit hit = s.castRay(centre, target - centre, t);
          if (!hit.hit || hit.distance < 1 - 1e-7) continue;  // hidden
          // Rotate the camera about its centre so that the target lands on the nearest pixel centre.
          const Eigen::Vector2d px(std::round(uv.x()), std::round(uv.y()));
          const Eigen::Vector3d want((px.x() - cam.cx) / cam.fx, (px.y() - cam.cy) / cam.fy, 1.0);
          const Eigen::Quaterniond q_new_old = Eigen::Quaterniond::FromTwoVectors(p_c, want);
          const SE3 T_w_new = T_w_c * SE3(q_new_old.conjugate(), Eigen::Vector3d::Zero());
          const RenderedFrame f = renderView(s, T_w_new, t, 0);
          const double z_expected = (T_w_new.inverse() * target).z();
          const double z = f.depth_m.at<float>(static_cast<int>(px.y()), static_cast<int>(px.x()));
          EXPECT_NEAR(z, z_expected, 1e-5) << "frame " << frame << " " << box.name << " corner " << ci;
          const Eigen::Vector3d back = T_w_new * cam.unprojectIdeal(px, z);
          EXPECT_LT((back - target).norm(), 1e-5) << "frame " << frame << " " << box.name << " corner " << ci;
          ++checked;
          ++in_frame;
          break;
        }
      }
    }
  }
  EXPECT_GE(checked, 12) << "too few visible corners to test";
}

TEST(SynthScene, MasksCoverExactlyTheMovingObjectsPixels) {
  const Scene s = makeScene(SceneKind::kDynamic, exact());
  const std::vector<int> cover = coverage(SceneKind::kDynamic, 300);
  const int frame = static_cast<int>(std::max_element(cover.begin(), cover.end()) - cover.begin());
  const RenderedFrame f = render(s, frame);
  const std::vector<Box> boxes = s.boxesAt(f.t_ns);
  const Eigen::Vector3d centre = f.T_w_c.translation();
  int masked = 0, mismatched = 0;
  std::map<int, int> per_id;
  for (int y = 0; y < f.instance_ids.rows; ++y)
    for (int x = 0; x < f.instance_ids.cols; ++x) {
      const int id = f.instance_ids.at<uint16_t>(y, x);
      // Every pixel whose ray first meets a person carries its id, and no other pixel does.
      const RayHit hit = castRay(boxes, centre, rayDir(s, f, x, y));
      if (hit.instance_id != id) ++mismatched;
      if (id == 0) continue;
      ++masked;
      ++per_id[id];
      // Every masked pixel's 3D point is on that person.
      EXPECT_EQ(s.movingObjectAt(backProject(s, f, x, y), f.t_ns, 1e-6), id) << "pixel " << x << "," << y;
    }
  EXPECT_EQ(mismatched, 0) << "frame " << frame;
  EXPECT_GT(masked, 1000) << "frame " << frame << ": persons should be in view";
  for (const auto& [id, n] : per_id) EXPECT_GE(id, 1);
}

TEST(SynthScene, PersonsAppearOnlyInTheScenesWithMovingObjects) {
  for (SceneKind kind : {SceneKind::kStatic, SceneKind::kLoop}) {
    const Scene s = makeScene(kind, exact());
    EXPECT_TRUE(s.movingObjects().empty());
    for (int i : {0, 100, 200}) EXPECT_EQ(cv::countNonZero(render(s, i).instance_ids), 0);
  }
  for (SceneKind kind : {SceneKind::kDynamic, SceneKind::kCrowded}) {
    const Scene s = makeScene(kind, exact());
    ASSERT_GE(s.movingObjects().size(), 2u);
    for (const auto& m : s.movingObjects()) {
      EXPECT_EQ(m.class_id, 0);
      EXPECT_EQ(m.class_name, "person");
    }
    const std::vector<int> cover = coverage(kind, 300);
    const int seen = static_cast<int>(std::count_if(cover.begin(), cover.end(), [](int n) { return n > 0; }));
    EXPECT_GT(seen, 150) << sceneKindName(kind) << ": persons in view in only " << seen << " of 300 frames";
  }
}

TEST(SynthScene, CrowdedScenePersonsCoverMoreThanHalfTheImageForAStretch) {
  const std::vector<int> cover = coverage(SceneKind::kCrowded, 300);
  int longest = 0, run = 0;
  for (int n : cover) {
    run = n > 160 * 120 / 2 ? run + 1 : 0;
    longest = std::max(longest, run);
  }
  EXPECT_GE(longest, 20) << "frames in a row with more than half the image covered";
  const std::vector<int> dyn = coverage(SceneKind::kDynamic, 300);
  EXPECT_LT(*std::max_element(dyn.begin(), dyn.end()), 160 * 120 / 2) << "the dynamic scene should not be crowded";
}

TEST(SynthScene, LoopWalkersOccludeTheFirstVisitOfTheLoopPlaceAndAreGoneAtTheReturn) {
  const int frames = defaultFrameCount(SceneKind::kLoopWalkers);
  const Scene s = makeScene(SceneKind::kLoopWalkers, exact(frames));
  ASSERT_EQ(s.movingObjects().size(), 3u);
  // The loop scene's lap, pose for pose.
  const Trajectory lap = makeScene(SceneKind::kLoop, exact(frames)).groundTruth(), gt = s.groundTruth();
  ASSERT_EQ(gt.size(), lap.size());
  for (size_t i = 0; i < gt.size(); i += 50) EXPECT_LT((gt[i].T_w_c.inverse() * lap[i].T_w_c).log().norm(), 1e-12) << i;
  const std::vector<int> cover = coverage(SceneKind::kLoopWalkers, frames);
  const int image = 160 * 120;
  // The first second, the loop place's first visit: walkers in every frame, over a third
  // of the image on average and over half of it at their closest.
  long first_second = 0;
  for (int i = 0; i < 30; ++i) {
    EXPECT_GT(cover[i], image / 10) << "frame " << i;
    first_second += cover[i];
  }
  const int closest = *std::max_element(cover.begin(), cover.begin() + 30);
  std::printf("loop_walkers: walkers cover %.0f %% of the image on average over the first second, %.0f %% at most\n",
              100.0 * first_second / (30.0 * image), 100.0 * closest / image);
  EXPECT_GT(first_second, 30L * image / 3);
  EXPECT_GT(closest, image / 2);
  // Out of view before they leave at 3 s (no one vanishes in sight), and none after: the
  // return to the place (the last 2 s) is clear.
  for (int i = 75; i < frames; ++i) EXPECT_EQ(cover[i], 0) << "frame " << i;
  EXPECT_TRUE(s.movingBoxes(s.frameTime(frames - 1)).empty());
  EXPECT_FALSE(s.movingBoxes(s.frameTime(0)).empty());
  EXPECT_EQ(parseSceneKind("loop_walkers"), SceneKind::kLoopWalkers);
}

TEST(SynthScene, LoopEndsWhereItStartedAfterGoingRoundTheRoom) {
  const Scene s = makeScene(SceneKind::kLoop, exact(defaultFrameCount(SceneKind::kLoop)));
  const Trajectory gt = s.groundTruth();
  ASSERT_EQ(static_cast<int>(gt.size()), s.frameCount());
  const SE3 d = gt.front().T_w_c.inverse() * gt.back().T_w_c;
  EXPECT_LT(d.translation().norm(), 0.03);
  EXPECT_LT(d.angle(), 1.0 * M_PI / 180);
  double far = 0, turned = 0;
  for (size_t i = 1; i < gt.size(); ++i) {
    far = std::max(far, (gt[i].T_w_c.translation() - gt[0].T_w_c.translation()).norm());
    turned += (gt[i - 1].T_w_c.inverse() * gt[i].T_w_c).angle();
  }
  EXPECT_GT(far, 1.0) << "the loop should leave its start";
  EXPECT_GT(turned, 1.9 * M_PI) << "the loop should look all round the room";
}

TEST(SynthScene, LapsRevisitTheSameWayEachLap) {
  SceneOptions o = exact(3 * 150 + 1);
  o.laps = 3;
  const Scene s = makeScene(SceneKind::kLoop, o);
  const Trajectory gt = s.groundTruth();
  // Frame i and frame i + 150 are the same pose one lap apart; half a lap away is far.
  for (int i : {0, 40, 150, 299}) {
    const SE3 d = gt[i].T_w_c.inverse() * gt[i + 150].T_w_c;
    EXPECT_LT(d.translation().norm(), 1e-6) << i;
    EXPECT_LT(d.angle(), 1e-6) << i;
  }
  EXPECT_GT((gt[0].T_w_c.translation() - gt[75].T_w_c.translation()).norm(), 1.0);
  EXPECT_NE(s.describe().find("laps 3"), std::string::npos);
  o.laps = 0;
  EXPECT_THROW(makeScene(SceneKind::kLoop, o), ConfigError);
}

TEST(SynthScene, CameraMovesAtHandheldSpeedsAndSeesSurfacesAtUsefulRange) {
  for (SceneKind kind : {SceneKind::kStatic, SceneKind::kDynamic, SceneKind::kLoop, SceneKind::kCrowded}) {
    const Scene s = makeScene(kind, exact(defaultFrameCount(kind)));
    const Trajectory gt = s.groundTruth();
    double v_max = 0, w_max = 0, v_sum = 0;
    for (size_t i = 1; i < gt.size(); ++i) {
      const double dt = nsToSeconds(gt[i].t_ns - gt[i - 1].t_ns);
      const SE3 d = gt[i - 1].T_w_c.inverse() * gt[i].T_w_c;
      v_max = std::max(v_max, d.translation().norm() / dt);
      v_sum += d.translation().norm() / dt;
      w_max = std::max(w_max, d.angle() / dt * 180 / M_PI);
    }
    const double v_mean = v_sum / (gt.size() - 1);
    EXPECT_LT(v_max, 0.5) << sceneKindName(kind);
    EXPECT_GT(v_mean, 0.03) << sceneKindName(kind);
    EXPECT_LT(w_max, 40.0) << sceneKindName(kind);
    // The static surfaces in front of the camera (centre ray) stay between 0.5 and 5.5 m.
    for (size_t i = 0; i < gt.size(); i += 10) {
      const Eigen::Vector3d c = gt[i].T_w_c.translation();
      const RayHit hit = castRay(s.staticBoxes(), c, gt[i].T_w_c.quaternion() * Eigen::Vector3d::UnitZ());
      ASSERT_TRUE(hit.hit);
      EXPECT_GT(hit.distance, 0.5) << sceneKindName(kind) << " frame " << i;
      EXPECT_LT(hit.distance, 5.5) << sceneKindName(kind) << " frame " << i;
      EXPECT_GT(s.staticSurfaceDistance(c), 0.3) << sceneKindName(kind) << " frame " << i << ": camera too close to a surface";
    }
  }
}

TEST(SynthScene, RendersAreDeterministicAndTheSeedChangesTheTextures) {
  SceneOptions o;  // with noise
  o.seed = 7;
  const RenderedFrame a = render(makeScene(SceneKind::kDynamic, o), 40);
  const RenderedFrame b = render(makeScene(SceneKind::kDynamic, o), 40);
  EXPECT_TRUE(sameBytes(a.bgr, b.bgr));
  EXPECT_TRUE(sameBytes(a.depth_m, b.depth_m));
  EXPECT_TRUE(sameBytes(a.instance_ids, b.instance_ids));
  o.seed = 8;
  const RenderedFrame c = render(makeScene(SceneKind::kDynamic, o), 40);
  EXPECT_FALSE(sameBytes(a.bgr, c.bgr));
  EXPECT_TRUE(sameBytes(a.instance_ids, c.instance_ids)) << "the seed must not move the geometry";
}

TEST(SynthScene, DepthNoiseFollowsTheKinectModel) {
  SceneOptions noisy;
  noisy.frames = defaultFrameCount(SceneKind::kLoop);
  const Scene sn = makeScene(SceneKind::kLoop, noisy);
  const Scene se = makeScene(SceneKind::kLoop, exact(noisy.frames));
  const double k = noisy.noise.sigma_k;
  // Residual statistics per depth band, pooled over frames seeing near and far walls.
  std::vector<double> sum2(8, 0), zsum(8, 0);
  std::vector<int> n(8, 0);
  int invalid = 0, total = 0;
  for (int frame : {0, 60, 120, 180, 240, 300, 360, 420}) {
    const RenderedFrame fn = render(sn, frame), fe = render(se, frame);
    for (int y = 0; y < fn.depth_m.rows; ++y)
      for (int x = 0; x < fn.depth_m.cols; ++x) {
        const float dn = fn.depth_m.at<float>(y, x), de = fe.depth_m.at<float>(y, x);
        ++total;
        if (!std::isfinite(dn)) {
          ++invalid;
          continue;
        }
        EXPECT_NEAR(std::round(dn * 5000.0), dn * 5000.0, 1e-2) << "depth must be quantised to 1/5000 m";
        if (!std::isfinite(de)) continue;
        const int band = static_cast<int>(de);
        if (band < 1 || band > 7) continue;
        sum2[band] += (dn - de) * (dn - de);
        zsum[band] += de * de;
        ++n[band];
      }
  }
  int bands = 0;
  for (int b = 1; b < 8; ++b) {
    if (n[b] < 5000) continue;
    const double sigma = std::sqrt(sum2[b] / n[b]);
    const double model = k * zsum[b] / n[b];  // k * mean(z^2)
    EXPECT_NEAR(sigma / model, 1.0, 0.2) << "depth band " << b << " m: sigma " << sigma << " model " << model;
    ++bands;
  }
  EXPECT_GE(bands, 2);
  const double dropped = static_cast<double>(invalid) / total;
  EXPECT_GT(dropped, noisy.noise.dropout_fraction * 0.8);
  EXPECT_LT(dropped, 0.1);
}

TEST(SynthScene, StaticFramesHaveManyOrbCornersAndLsdSegments) {
  const Scene s = makeScene(SceneKind::kStatic, SceneOptions{});
  for (int frame : {0, 150}) {
    cv::Mat grey;
    cv::cvtColor(render(s, frame).bgr, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> kp;
    cv::ORB::create(1000)->detect(grey, kp);
    EXPECT_GE(kp.size(), 500u) << "frame " << frame;
    std::vector<cv::Vec4f> segments;
    cv::createLineSegmentDetector()->detect(grey, segments);
    const auto long_ones = std::count_if(segments.begin(), segments.end(), [](const cv::Vec4f& l) {
      return std::hypot(l[2] - l[0], l[3] - l[1]) > 30;
    });
    EXPECT_GE(segments.size(), 300u) << "frame " << frame;
    EXPECT_GE(long_ones, 80) << "frame " << frame;
  }
}

TEST(SynthScene, SurfaceQueriesAgreeWithTheLayout) {
  const Scene s = makeScene(SceneKind::kDynamic, exact());
  EXPECT_NEAR(s.surfaceDistance({0.3, -1.0, 0.0}, s.frameTime(0)), 0.0, 1e-12);  // on the floor
  EXPECT_NEAR(s.staticSurfaceDistance({0.3, -1.0, 0.2}), 0.2, 1e-12);
  EXPECT_NEAR(s.staticSurfaceDistance({0.0, 0.0, 2.9}), 0.1, 1e-12);  // below the ceiling
  // The centre of a person's torso is on that person; corners and edges are consistent.
  const std::vector<Box> parts = s.movingBoxes(s.frameTime(30));
  ASSERT_FALSE(parts.empty());
  EXPECT_EQ(s.movingObjectAt(parts[2].T_w_b.translation(), s.frameTime(30)), parts[2].instance_id);
  EXPECT_EQ(s.movingObjectAt({0.3, -1.0, 0.0}, s.frameTime(30)), 0);
  EXPECT_EQ(s.staticCorners().size(), 8 * s.staticBoxes().size());
  EXPECT_EQ(s.staticEdges().size(), 12 * s.staticBoxes().size());
  for (const Segment3d& e : s.staticEdges()) EXPECT_LT(s.staticSurfaceDistance(0.5 * (e.a + e.b)), 1e-9);
}

TEST(SynthTexture, GridLookupsEqualTheFullWalkAndSeedsDiffer) {
  const Material all[] = {Material::kWall,   Material::kFloor, Material::kCeiling,  Material::kWood, Material::kCardboard,
                          Material::kPoster, Material::kShirt, Material::kTrousers, Material::kSkin, Material::kHair};
  for (Material m : all) {
    const FaceTexture a(m, 11, 6.0, 3.0), b(m, 12, 6.0, 3.0);
    int differ = 0;
    for (int i = 0; i < 20000; ++i) {
      // Deterministic points, some exactly on grid-cell and face boundaries.
      const double s = (i % 200) * 0.03 + (i % 7 == 0 ? 0.0 : 0.0123 * (i % 3)), t = (i / 200) * 0.03;
      const Rgb c = a.colour(s, t), r = a.colourFromRoot(s, t);
      ASSERT_TRUE(c.r == r.r && c.g == r.g && c.b == r.b) << materialName(m) << " at " << s << "," << t;
      const Rgb o = b.colour(s, t);
      differ += (o.r != c.r || o.g != c.g || o.b != c.b);
    }
    EXPECT_GT(differ, 1000) << materialName(m) << ": another seed should give another texture";
    EXPECT_GT(a.leafCount(), 10u) << materialName(m);
  }
}

TEST(SynthScene, BadOptionsAreRefused) {
  SceneOptions o;
  o.frames = 0;
  EXPECT_THROW(makeScene(SceneKind::kStatic, o), ConfigError);
  o = SceneOptions{};
  o.aa_samples = 0;
  EXPECT_THROW(makeScene(SceneKind::kStatic, o), ConfigError);
  EXPECT_THROW(parseSceneKind("kitchen"), ConfigError);
  EXPECT_EQ(parseSceneKind("crowded"), SceneKind::kCrowded);
  const Scene s = makeScene(SceneKind::kStatic, SceneOptions{});
  EXPECT_THROW(render(s, s.frameCount()), ConfigError);
}

TEST(SynthDataset, WrittenFolderHasTheDocumentedFilesAndReadsBack) {
  SceneOptions o;
  o.frames = 4;
  o.width = 160;
  o.height = 120;
  const Scene s = makeScene(SceneKind::kDynamic, o);
  const std::string dir = test::scratchDir("synth_dataset");
  DatasetOptions d;
  d.depth_offset_ns = 3'000'000;
  int calls = 0;
  d.progress = [&](int done, int total) {
    ++calls;
    EXPECT_EQ(total, 4);
    EXPECT_EQ(done, calls);
  };
  writeDataset(s, dir, d);
  EXPECT_EQ(calls, 4);
  for (const char* f : {"rgb.txt", "depth.txt", "masks.txt", "groundtruth.txt", "camera.xml", "scene.txt",
                        "masks/instances.txt"})
    EXPECT_TRUE(fs::exists(dir + "/" + f)) << f;

  const auto rgb = readIndex(dir + "/rgb.txt"), depth = readIndex(dir + "/depth.txt"),
             masks = readIndex(dir + "/masks.txt");
  ASSERT_EQ(rgb.size(), 4u);
  ASSERT_EQ(depth.size(), 4u);
  ASSERT_EQ(masks.size(), 4u);
  const Trajectory gt = readTumTrajectory(dir + "/groundtruth.txt");
  ASSERT_EQ(gt.size(), 4u);
  const PinholeCamera cam = loadCameraFile(dir + "/camera.xml");
  EXPECT_EQ(cam.name, "synthetic");
  EXPECT_EQ(cam.width, 160);
  EXPECT_DOUBLE_EQ(cam.fx, s.camera().fx);
  EXPECT_DOUBLE_EQ(cam.cx, s.camera().cx);
  EXPECT_DOUBLE_EQ(cam.depth_scale, 5000.0);
  for (int i = 0; i < 4; ++i) {
    TimeNs t = 0, td = 0;
    ASSERT_TRUE(parseSecondsStamp(rgb[i].first, &t));
    ASSERT_TRUE(parseSecondsStamp(depth[i].first, &td));
    EXPECT_EQ(t, s.frameTime(i));
    EXPECT_EQ(td, s.frameTime(i) + 3'000'000);
    EXPECT_EQ(masks[i].first, rgb[i].first);
    EXPECT_EQ(gt[i].t_ns, t);
    EXPECT_LT((gt[i].T_w_c.translation() - s.cameraPose(i).translation()).norm(), 1e-6);
    EXPECT_LT((gt[i].T_w_c.inverse() * s.cameraPose(i)).angle(), 1e-6);

    const cv::Mat c = cv::imread(dir + "/" + rgb[i].second, cv::IMREAD_UNCHANGED);
    const cv::Mat z = cv::imread(dir + "/" + depth[i].second, cv::IMREAD_UNCHANGED);
    const cv::Mat m = cv::imread(dir + "/" + masks[i].second, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(c.type(), CV_8UC3);
    ASSERT_EQ(z.type(), CV_16UC1);
    ASSERT_EQ(m.type(), CV_16UC1);
    EXPECT_EQ(c.size(), cv::Size(160, 120));
    EXPECT_EQ(z.size(), cv::Size(160, 120));
    EXPECT_EQ(m.size(), cv::Size(160, 120));
    // The files hold exactly what render() gives.
    const RenderedFrame f = render(s, i);
    EXPECT_TRUE(sameBytes(c, f.bgr));
    EXPECT_TRUE(sameBytes(m, f.instance_ids));
    EXPECT_TRUE(sameBytes(z, metresToDepth(f.depth_m, 5000.0)));
  }
  const std::string instances = slurp(dir + "/masks/instances.txt");
  EXPECT_NE(instances.find("\n1 0 person\n"), std::string::npos) << instances;
  EXPECT_NE(instances.find("\n2 0 person\n"), std::string::npos) << instances;
  EXPECT_NE(slurp(dir + "/scene.txt").find("scene dynamic"), std::string::npos);

  // Same scene, same bytes.
  const std::string again = test::scratchDir("synth_dataset_again");
  writeDataset(s, again, DatasetOptions{});
  for (const auto& [stamp, file] : rgb) EXPECT_EQ(slurp(dir + "/" + file), slurp(again + "/" + file)) << file;
  for (const auto& [stamp, file] : masks) EXPECT_EQ(slurp(dir + "/" + file), slurp(again + "/" + file)) << file;
  EXPECT_EQ(slurp(dir + "/groundtruth.txt"), slurp(again + "/groundtruth.txt"));
  EXPECT_EQ(slurp(dir + "/scene.txt"), slurp(again + "/scene.txt"));
}

TEST(SynthDataset, PreviewShowsThreeFramesSideBySide) {
  SceneOptions o;
  o.frames = 30;
  o.width = 160;
  o.height = 120;
  const Scene s = makeScene(SceneKind::kCrowded, o);
  const std::vector<int> frames = previewFrames(s);
  ASSERT_EQ(frames.size(), 3u);
  for (int f : frames) {
    EXPECT_GE(f, 0);
    EXPECT_LT(f, 30);
  }
  const std::string path = test::scratchDir("synth_preview") + "/preview.png";
  writePreview(s, path);
  const cv::Mat sheet = cv::imread(path);
  EXPECT_EQ(sheet.cols, 3 * 80);
  EXPECT_EQ(sheet.rows, 3 * 60);
}

TEST(SceneTest, TwinShelfAddsCopiesOfTheShelfsThingsWithTheirTexturesInAnotherLayout) {
  const Scene plain = makeScene(SceneKind::kStatic);
  SceneOptions o;
  o.twin_shelf = true;
  const Scene twin = makeScene(SceneKind::kStatic, o);
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < twin.staticBoxes().size(); ++i) index[twin.staticBoxes()[i].name] = i;
  for (const Box& b : plain.staticBoxes()) EXPECT_EQ(b.name.rfind("twin_", 0), std::string::npos) << "no copies by default";
  ASSERT_EQ(twin.staticBoxes().size(), plain.staticBoxes().size() + 4);
  const SE3 T = twinShelfTransform();
  std::vector<Eigen::Vector3d> offsets;  // each copy's centre minus where its original maps to
  for (size_t i = plain.staticBoxes().size(); i < twin.staticBoxes().size(); ++i) {
    const Box& copy = twin.staticBoxes()[i];
    ASSERT_EQ(copy.name.rfind("twin_shelf/", 0), 0u) << copy.name;
    const size_t k = index.at(copy.name.substr(5));
    const Box& original = twin.staticBoxes()[k];
    EXPECT_EQ(copy.texture_seed, original.texture_seed) << copy.name;
    EXPECT_EQ(copy.half_size, original.half_size) << copy.name;
    EXPECT_EQ(copy.materials, original.materials) << copy.name;
    // Every face has the original's texture (sampled on a grid).
    for (int f = 0; f < 6; ++f)
      for (double s = 0.01; s < 0.2; s += 0.037)
        for (double t = 0.01; t < 0.2; t += 0.041) {
          const Rgb a = twin.staticTexture(i, f).colour(s, t), b = twin.staticTexture(k, f).colour(s, t);
          ASSERT_TRUE(a.r == b.r && a.g == b.g && a.b == b.b) << copy.name << " face " << f;
        }
    offsets.push_back(copy.T_w_b.translation() - T * original.T_w_b.translation());
  }
  // Another layout: one common offset would be the same arrangement moved.
  double spread = 0;
  for (const Eigen::Vector3d& d : offsets) spread = std::max(spread, (d - offsets.front()).norm());
  EXPECT_GT(spread, 0.2);
}
