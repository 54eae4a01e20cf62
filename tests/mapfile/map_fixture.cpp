#include "map_fixture.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>

#include "../system/synthetic_cache.h"
#include "camera/camera_file.h"
#include "core/option_table.h"
#include "eval/trajectory_eval.h"
#include "core/error.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "mapfile/map_file.h"
#include "system/system.h"

namespace plslam::test {

namespace {
struct Holder {
  BuiltMap built;
  std::unique_ptr<System> system;
  Map loaded;
};

/// The static scene has no instances, dense clouds or moving pixels: give every other
/// keyframe made-up ones so that every field goes through the file.
void decorate(Map* map, const PinholeCamera& camera) {
  int n = 0;
  for (const auto& [id, kf_const] : map->keyframes()) {
    KeyFrame* kf = map->keyframe(id);
    if (n++ % 2) continue;
    KeyframeInstance person;
    person.class_id = 0;
    person.class_name = "person";
    person.dynamic = true;
    person.box = cv::Rect(10 + n, 20, 64, 128);
    person.pixels = 4000 + n;
    person.centroid_c = Eigen::Vector3d(0.1 * n, -0.2, 1.5);
    KeyframeInstance chair;
    chair.class_id = 56;
    chair.class_name = "chair";
    kf->instances = {person, chair};  // the chair has no depth: NaN centroid
    for (int i = 0; i < 50; ++i) {
      DensePoint d;
      d.p_c = Eigen::Vector3f(0.01f * i, -0.02f * i, 1.0f + 0.001f * i);
      d.r = static_cast<uint8_t>(i * 5);
      d.g = static_cast<uint8_t>(255 - i);
      d.b = static_cast<uint8_t>(i);
      d.class_id = static_cast<int16_t>(i % 3 - 1);
      kf->dense.push_back(d);
    }
    cv::Mat mask(camera.height, camera.width, CV_8U, cv::Scalar(255));
    mask(cv::Rect(5 + n, 7, 40, 33)).setTo(0);
    mask.at<uint8_t>(camera.height - 1, camera.width - 1) = 17;
    kf->dynamic_mask = mask;
  }
}

/// Runs SLAM over the first kMapFrames frames (sequential, default options).
Holder* runSlam() {
  auto* h = new Holder;
  BuiltMap& b = h->built;
  b.dataset = syntheticSequence(synth::SceneKind::kStatic, 120);
  b.camera = loadCameraFile(b.dataset + "/camera.xml");
  SystemOptions options;
  options.sequential = true;
  OptionTable table;
  bindOptions(&table, &options);
  b.config_yaml = table.toYaml("mapfile test configuration");
  DatasetOptions dopt;
  dopt.max_frames = kMapFrames;
  TumDataset data = TumDataset::open(b.dataset, b.camera, dopt);
  h->system = std::make_unique<System>(b.camera, options);
  h->system->start();
  RgbdFrame frame;
  while (data.next(&frame)) h->system->feed(frame);
  h->system->finish();
  b.trajectory = h->system->trajectory();
  b.ate = evaluate(data.groundtruth(), b.trajectory).ate.stats.rmse;
  return h;
}

Holder* fromCacheOrSlam() {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "plslam_tests" / ("mapfile_static_" + std::to_string(kMapFrames));
  fs::create_directories(dir);
  const std::string lock_path = dir.string() + ".lock";
  const int fd = ::open(lock_path.c_str(), O_CREAT | O_RDWR, 0644);
  if (fd >= 0) ::flock(fd, LOCK_EX);
  Holder* h = nullptr;
  try {
    if (fs::exists(dir / "trajectory.txt")) {  // written last: its presence means the cache is complete
      LoadedMap l = loadMap((dir / "map.plmap").string());
      h = new Holder;
      BuiltMap& b = h->built;
      b.dataset = syntheticSequence(synth::SceneKind::kStatic, 120);
      b.camera = l.camera;
      b.config_yaml = l.config_yaml;
      h->loaded = std::move(l.map);
      b.trajectory = readTumTrajectory((dir / "trajectory.txt").string());
      b.ate = evaluate(readTumTrajectory(b.dataset + "/groundtruth.txt"), b.trajectory).ate.stats.rmse;
    }
  } catch (const Error&) {
    delete h;
    h = nullptr;  // a cache from another format version: build again
  }
  if (!h) {
    h = runSlam();
    saveMap((dir / "map.plmap").string(), h->system->map(), h->built.camera, h->built.config_yaml);
    writeTumTrajectory((dir / "trajectory.txt").string(), h->built.trajectory, "mapfile test cache");
    h->loaded = std::move(const_cast<Map&>(h->system->map()));
  }
  if (fd >= 0) {
    ::flock(fd, LOCK_UN);
    ::close(fd);
  }
  decorate(&h->loaded, h->built.camera);
  h->built.map = &h->loaded;
  return h;
}

bool sameFloat(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

void expectSameMat(const cv::Mat& a, const cv::Mat& b, const std::string& what) {
  ASSERT_EQ(a.empty(), b.empty()) << what;
  if (a.empty()) return;
  ASSERT_EQ(a.rows, b.rows) << what;
  ASSERT_EQ(a.cols, b.cols) << what;
  ASSERT_EQ(a.type(), b.type()) << what;
  for (int r = 0; r < a.rows; ++r)
    ASSERT_EQ(std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize()), 0) << what << " row " << r;
}

void expectSameVec(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const std::string& what) {
  EXPECT_TRUE(sameFloat(a.x(), b.x()) && sameFloat(a.y(), b.y())) << what;
}
void expectSameVec(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const std::string& what) {
  EXPECT_TRUE(sameFloat(a.x(), b.x()) && sameFloat(a.y(), b.y()) && sameFloat(a.z(), b.z())) << what;
}
}  // namespace

const BuiltMap& builtMap() {
  static Holder* holder = fromCacheOrSlam();
  return holder->built;
}

const BuiltMap& freshlyBuiltMap() {
  static Holder* holder = [] {
    Holder* h = runSlam();
    Map& map = const_cast<Map&>(h->system->map());
    decorate(&map, h->built.camera);
    h->built.map = &map;
    return h;
  }();
  return holder->built;
}

void expectMapsEqual(const Map& a, const Map& b) {
  ASSERT_EQ(a.keyframes().size(), b.keyframes().size());
  ASSERT_EQ(a.points().size(), b.points().size());
  ASSERT_EQ(a.lines().size(), b.lines().size());
  for (auto ia = a.keyframes().begin(), ib = b.keyframes().begin(); ia != a.keyframes().end(); ++ia, ++ib) {
    const KeyFrame& x = ia->second;
    const KeyFrame& y = ib->second;
    const std::string w = "keyframe " + std::to_string(x.id);
    ASSERT_EQ(ia->first, ib->first);
    ASSERT_EQ(x.id, y.id);
    EXPECT_EQ(x.t_ns, y.t_ns) << w;
    EXPECT_EQ(x.T_w_c.quaternion().coeffs(), y.T_w_c.quaternion().coeffs()) << w;
    EXPECT_EQ(x.T_w_c.translation(), y.T_w_c.translation()) << w;
    ASSERT_EQ(x.features.points.size(), y.features.points.size()) << w;
    for (size_t i = 0; i < x.features.points.size(); ++i) {
      const Keypoint &p = x.features.points[i], &q = y.features.points[i];
      expectSameVec(p.uv_raw, q.uv_raw, w + " uv_raw");
      expectSameVec(p.uv, q.uv, w + " uv");
      EXPECT_EQ(p.octave, q.octave) << w;
      EXPECT_TRUE(sameFloat(p.angle, q.angle)) << w;
      EXPECT_TRUE(sameFloat(p.depth_m, q.depth_m)) << w;
    }
    ASSERT_EQ(x.features.lines.size(), y.features.lines.size()) << w;
    for (size_t i = 0; i < x.features.lines.size(); ++i) {
      const Segment2D &p = x.features.lines[i], &q = y.features.lines[i];
      expectSameVec(p.p_raw, q.p_raw, w + " p_raw");
      expectSameVec(p.q_raw, q.q_raw, w + " q_raw");
      expectSameVec(p.p, q.p, w + " p");
      expectSameVec(p.q, q.q, w + " q");
      EXPECT_EQ(p.octave, q.octave) << w;
    }
    expectSameMat(x.features.point_descriptors, y.features.point_descriptors, w + " point descriptors");
    expectSameMat(x.features.line_descriptors, y.features.line_descriptors, w + " line descriptors");
    EXPECT_EQ(x.point_ids, y.point_ids) << w;
    EXPECT_EQ(x.line_ids, y.line_ids) << w;
    expectSameMat(x.dynamic_mask, y.dynamic_mask, w + " dynamic mask");
    ASSERT_EQ(x.instances.size(), y.instances.size()) << w;
    for (size_t i = 0; i < x.instances.size(); ++i) {
      const KeyframeInstance &p = x.instances[i], &q = y.instances[i];
      EXPECT_EQ(p.class_id, q.class_id) << w;
      EXPECT_EQ(p.class_name, q.class_name) << w;
      EXPECT_EQ(p.dynamic, q.dynamic) << w;
      EXPECT_EQ(p.box, q.box) << w;
      EXPECT_EQ(p.pixels, q.pixels) << w;
      expectSameVec(p.centroid_c, q.centroid_c, w + " centroid");
    }
    ASSERT_EQ(x.dense.size(), y.dense.size()) << w;
    for (size_t i = 0; i < x.dense.size(); ++i) {
      const DensePoint &p = x.dense[i], &q = y.dense[i];
      EXPECT_EQ(p.p_c, q.p_c) << w;
      EXPECT_EQ(p.r, q.r) << w;
      EXPECT_EQ(p.g, q.g) << w;
      EXPECT_EQ(p.b, q.b) << w;
      EXPECT_EQ(p.class_id, q.class_id) << w;
    }
  }
  for (auto ia = a.points().begin(), ib = b.points().begin(); ia != a.points().end(); ++ia, ++ib) {
    const MapPoint &x = ia->second, &y = ib->second;
    const std::string w = "map point " + std::to_string(x.id);
    ASSERT_EQ(x.id, y.id);
    ASSERT_EQ(ia->first, ib->first);
    EXPECT_EQ(x.p_w, y.p_w) << w;
    expectSameMat(x.descriptor, y.descriptor, w + " descriptor");
    EXPECT_EQ(x.observations, y.observations) << w;
    EXPECT_EQ(x.first_keyframe, y.first_keyframe) << w;
    EXPECT_EQ(x.visible, y.visible) << w;
    EXPECT_EQ(x.found, y.found) << w;
  }
  for (auto ia = a.lines().begin(), ib = b.lines().begin(); ia != a.lines().end(); ++ia, ++ib) {
    const MapLine &x = ia->second, &y = ib->second;
    const std::string w = "map line " + std::to_string(x.id);
    ASSERT_EQ(x.id, y.id);
    ASSERT_EQ(ia->first, ib->first);
    EXPECT_EQ(x.P_w, y.P_w) << w;
    EXPECT_EQ(x.Q_w, y.Q_w) << w;
    expectSameMat(x.descriptor, y.descriptor, w + " descriptor");
    EXPECT_EQ(x.observations, y.observations) << w;
    EXPECT_EQ(x.first_keyframe, y.first_keyframe) << w;
    EXPECT_EQ(x.visible, y.visible) << w;
    EXPECT_EQ(x.found, y.found) << w;
  }
}

}  // namespace plslam::test
