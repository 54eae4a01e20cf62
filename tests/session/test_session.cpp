// The transport-neutral session under the ROS node: configuration from switches, frames
// pushed from another thread, outputs; and the robot frame conventions (REP-103/105).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "calibration/base_transform.h"
#include "camera/camera_file.h"
#include "core/map_frame.h"
#include "core/error.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "dense/dense_products.h"
#include "session/live_session.h"
#include "session/robot_frames.h"
#include "support/test_support.h"
#include "synthetic_cache.h"

using namespace plslam;

TEST(RobotFrames, OpticalAxesBecomeForwardLeftUp) {
  const RobotFrames frames;  // no calibration: the level camera at the base origin
  const SE3 T_base_cam = frames.T_base_cam();
  EXPECT_TRUE((T_base_cam * Eigen::Vector3d(0, 0, 1)).isApprox(Eigen::Vector3d(1, 0, 0)));   // forward
  EXPECT_TRUE((T_base_cam * Eigen::Vector3d(-1, 0, 0)).isApprox(Eigen::Vector3d(0, 1, 0)));  // left
  EXPECT_TRUE((T_base_cam * Eigen::Vector3d(0, -1, 0)).isApprox(Eigen::Vector3d(0, 0, 1)));  // up
  // At the first frame the base is at map's origin, whatever T_base_cam is.
  const SE3 mounted(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(0.09, 0.01, 0.18));
  const RobotFrames robot(mounted);
  const SE3 map = robot.provisionalMapFrame();
  EXPECT_TRUE(robot.T_map_base(map, SE3()).translation().isZero(1e-12));
  // The camera moving 1 m along its optical axis moves the base 1 m forward in map.
  const SE3 T_w_c(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 1));
  EXPECT_TRUE(robot.T_map_base(map, T_w_c).translation().isApprox(mounted * Eigen::Vector3d(0, 0, 1) - mounted.translation()));
  EXPECT_TRUE(robot.T_map_cam(map, T_w_c).translation().isApprox(mounted * Eigen::Vector3d(0, 0, 1)));
}

TEST(RunConfig, SwitchesOverTheFileAndRefusedCombinations) {
  RunSwitches s;
  s.no_lines = true;
  s.no_loop = true;
  s.dynamic_classes = "person,dog";
  const RunConfig c = makeRunConfig(s, "test");
  EXPECT_FALSE(c.options.use_lines);
  EXPECT_FALSE(c.options.use_loop);
  ASSERT_TRUE(c.options.segmenter.dynamic_classes.has_value());
  EXPECT_EQ(c.options.segmenter.dynamic_classes->size(), 2u);
  EXPECT_NE(c.config_yaml.find("use_lines: false"), std::string::npos) << c.config_yaml;
  s.localize = true;
  EXPECT_THROW(makeRunConfig(s, "test"), ConfigError);
}

namespace {
std::string writeConfig(const std::string& name, const std::string& text) {
  const std::string path = test::scratchDir("run_config") + "/" + name;
  std::ofstream(path) << text;
  return path;
}
}  // namespace

TEST(RunConfig, SegmenterKeysGiveTheSameConfigurationAsTheSwitches) {
  RunSwitches by_file;
  by_file.config = writeConfig("segmenter.yaml",
                               "segmenter:\n  backend: yolo\n  model: /models/seg.onnx\n  classes: /models/names.txt\n"
                               "  dynamic_classes: \"person, dog\"\n  allow_missing_model: true\n");
  RunSwitches by_switch;
  by_switch.segmenter = "/models/seg.onnx";
  by_switch.classes = "/models/names.txt";
  by_switch.dynamic_classes = "person,dog";
  by_switch.allow_missing_model = true;
  const RunConfig a = makeRunConfig(by_file, "test"), b = makeRunConfig(by_switch, "test");
  for (const SegmenterOptions* s : {&a.options.segmenter, &b.options.segmenter}) {
    EXPECT_EQ(s->kind, SegmenterKind::kYolo);
    EXPECT_EQ(s->yolo.model_path, "/models/seg.onnx");
    EXPECT_EQ(s->classes_file, "/models/names.txt");
    ASSERT_TRUE(s->dynamic_classes.has_value());
    EXPECT_EQ(*s->dynamic_classes, (std::vector<std::string>{"person", "dog"}));
    EXPECT_TRUE(s->allow_missing_model);
  }
  EXPECT_EQ(a.config_yaml, b.config_yaml) << "the effective configuration written beside the outputs is the same";
  EXPECT_NE(a.config_yaml.find("backend: \"yolo\""), std::string::npos) << a.config_yaml;

  // The written configuration gives it back (plslam run --config OUT/config.yaml repeats the run).
  RunSwitches again;
  again.config = writeConfig("effective.yaml", b.config_yaml);
  EXPECT_EQ(makeRunConfig(again, "test").config_yaml, b.config_yaml);
}

TEST(RunConfig, SegmenterSwitchOverridesTheKeyAndABadValueNamesTheKey) {
  RunSwitches s;
  s.config = writeConfig("yolo.yaml", "segmenter:\n  backend: yolo\n  model: /models/seg.onnx\n  classes: /a.txt\n");
  EXPECT_EQ(makeRunConfig(s, "test").options.segmenter.kind, SegmenterKind::kYolo);
  s.segmenter = "replay";
  s.classes = "/b.txt";
  const RunConfig c = makeRunConfig(s, "test");
  EXPECT_EQ(c.options.segmenter.kind, SegmenterKind::kReplay);
  EXPECT_EQ(c.options.segmenter.classes_file, "/b.txt");
  s.segmenter = "yolo";  // the model of the key
  EXPECT_EQ(makeRunConfig(s, "test").options.segmenter.yolo.model_path, "/models/seg.onnx");

  RunSwitches bad;
  bad.config = writeConfig("bad.yaml", "segmenter:\n  backend: yolov9\n");
  try {
    makeRunConfig(bad, "test");
    FAIL() << "a bad segmenter.backend must be refused";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("segmenter.backend"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("yolov9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad.config), std::string::npos) << e.what();
  }
}

TEST(RunConfig, SavedMapGivesItsConfigurationButNotItsSegmenter) {
  const std::string path = test::scratchDir("run_config_map") + "/saved.plmap";  // writeConfig empties its own folder
  saveMap(path, Map(), loadCameraFile(test::sourceDir() + "/calib/tum_freiburg1.xml"),
          "system:\n  use_lines: false\nsegmenter:\n  backend: replay\n  classes: /recorded/names.txt\n");
  RunSwitches s;
  s.map = path;
  const RunConfig c = makeRunConfig(s, "test");
  EXPECT_FALSE(c.options.use_lines) << "the map's own configuration is the base";
  EXPECT_EQ(c.options.segmenter.kind, SegmenterKind::kNone) << "the segmenter is the session's";
  EXPECT_EQ(c.options.segmenter.classes_file, "");
  s.config = writeConfig("yolo_over_map.yaml", "segmenter:\n  backend: yolo\n  model: /m.onnx\n");
  EXPECT_EQ(makeRunConfig(s, "test").options.segmenter.kind, SegmenterKind::kYolo) << "this session's file sets it";
}

TEST(LiveSession, PushedFramesWithoutDropsTrackLikeTheSystem) {
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 40);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  RunSwitches s;
  s.sequential = true;
  SessionOptions so;
  so.drop_frames = false;
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<FrameOutcome> outcomes;
  session.setFrameListener([&](const FrameOutcome& f) { outcomes.push_back(f); });
  session.start();
  TumDataset dataset = TumDataset::open(folder, camera);
  std::thread producer([&] {
    RgbdFrame frame;
    while (dataset.next(&frame)) session.push(deepCopy(frame));
  });
  producer.join();
  session.stop();
  const SessionCounts c = session.counts();
  EXPECT_EQ(c.received, 40);
  EXPECT_EQ(c.processed, 40);
  EXPECT_EQ(c.dropped, 0);
  ASSERT_EQ(outcomes.size(), 40u);
  EXPECT_GT(session.sparseMap().points.size(), 100u);

  // The same frames straight into a System give the same trajectory.
  SystemOptions options = makeRunConfig(s, "test").options;
  System direct(camera, options);
  direct.start();
  dataset.rewind();
  RgbdFrame frame;
  while (dataset.next(&frame)) direct.feed(frame);
  direct.finish();
  const Trajectory a = session.system().trajectory(), b = direct.trajectory();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].T_w_c.translation().isApprox(b[i].T_w_c.translation(), 1e-12)) << i;
  EXPECT_TRUE(outcomes.back().tracked);

  const std::string out = test::scratchDir("session") + "/out";
  session.writeOutputs(out, nullptr, false);
  EXPECT_EQ(readTumTrajectory(out + "/trajectory.txt").size(), a.size());
  EXPECT_TRUE(std::filesystem::exists(out + "/map.plmap"));
}

namespace {

// The frames of the synthetic static sequence, depth as a sensor reading measured = scale * true.
std::vector<RgbdFrame> scaledDepthFrames(const std::string& folder, const PinholeCamera& camera, double scale) {
  TumDataset dataset = TumDataset::open(folder, camera);
  std::vector<RgbdFrame> frames;
  RgbdFrame frame;
  while (dataset.next(&frame)) {
    RgbdFrame f = deepCopy(frame);
    f.depth_m *= scale;
    frames.push_back(f);
  }
  return frames;
}

// Mean distance of the poses from the first one: the size of the trajectory.
double extent(const Trajectory& t) {
  double sum = 0;
  for (const StampedPose& p : t) sum += (p.T_w_c.translation() - t.front().T_w_c.translation()).norm();
  return sum / t.size();
}

}  // namespace

// A depth sensor reading 8 % long: uncorrected, the trajectory is 8 % larger than the truth;
// with calibration.depth_scale 1.08 (as plslam calib depth reports it) it is the truth's size.
TEST(RunConfig, DepthScaleOfTheCalibrationUndoesAKnownDepthScale) {
  constexpr double kScale = 1.08;
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 60);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const std::vector<RgbdFrame> frames = scaledDepthFrames(folder, camera, kScale);
  const double truth = extent(TumDataset::open(folder, camera).groundtruth());
  const std::string cfg = test::scratchDir("depth_scale") + "/depth.yaml";
  std::ofstream(cfg) << "calibration:\n  depth_scale: " << kScale << "\n  depth_offset_m: 0\n";
  auto run = [&](const std::string& config) {
    RunSwitches s;
    s.sequential = true;
    s.no_loop = true;
    s.config = config;
    System slam(camera, makeRunConfig(s, "test").options);
    slam.start();
    for (const RgbdFrame& f : frames) slam.feed(f);
    slam.finish();
    return slam.trajectory();
  };
  const Trajectory raw = run(""), corrected = run(cfg);
  ASSERT_GT(raw.size(), 50u);
  ASSERT_GT(corrected.size(), 50u);
  std::printf("depth read x%.2f: trajectory extent / truth %.4f uncorrected, %.4f with calibration.depth_scale\n", kScale,
              extent(raw) / truth, extent(corrected) / truth);
  EXPECT_NEAR(extent(raw) / truth, kScale, 0.02);
  EXPECT_NEAR(extent(corrected) / truth, 1.0, 0.02);
  // The same frames, one scaled: the trajectories differ by the depth scale.
  EXPECT_NEAR(extent(raw) / extent(corrected), kScale, 0.005);
}

TEST(RunConfig, BaseSwitchLoadsTheMountingAndRefusesABadFile) {
  const std::string dir = test::scratchDir("run_config_base");
  calib::CameraToBase mounting;
  mounting.T_b_c = SE3(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(0.1, 0.0, 0.2));
  calib::saveCameraToBase(dir + "/base.yaml", mounting);
  RunSwitches s;
  EXPECT_FALSE(makeRunConfig(s, "test").options.dense.T_base_cam.has_value());
  s.base = dir + "/base.yaml";
  const RunConfig c = makeRunConfig(s, "test");
  ASSERT_TRUE(c.options.dense.T_base_cam.has_value());
  EXPECT_LT((*c.options.dense.T_base_cam * mounting.T_b_c.inverse()).angle(), 1e-9);
  EXPECT_NE(c.config_yaml.find("camera_to_base: \"" + s.base + "\""), std::string::npos) << c.config_yaml;
  s.base = dir + "/missing.yaml";
  EXPECT_THROW(makeRunConfig(s, "test"), IoError);
}

// The session fixes one map frame after its first keyframes; the poses it reports from then
// on are in it, and so are the files it writes (map_frame.yaml, trajectory_base.txt).
TEST(LiveSession, ReportedMapFrameIsTheOneOfTheWrittenFiles) {
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 40);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const std::string dir = test::scratchDir("session_frame");
  calib::CameraToBase mounting;
  mounting.T_b_c = SE3(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(0.1, 0.0, 0.2));
  calib::saveCameraToBase(dir + "/base.yaml", mounting);
  RunSwitches s;
  s.sequential = true;
  s.base = dir + "/base.yaml";
  SessionOptions so;
  so.drop_frames = false;
  so.live_maps = false;  // the frame from the map points (with maps while running: their dense floor, tested below)
  so.map_frame_keyframes = 2;
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<FrameOutcome> outcomes;
  session.setFrameListener([&](const FrameOutcome& f) { outcomes.push_back(f); });
  session.start();
  TumDataset dataset = TumDataset::open(folder, camera);
  RgbdFrame frame;
  while (dataset.next(&frame)) session.push(deepCopy(frame));
  session.stop();
  ASSERT_TRUE(session.mapFrame().has_value());
  ASSERT_TRUE(outcomes.back().map_frame_fixed);
  EXPECT_FALSE(outcomes.front().map_frame_fixed) << "fixed after 2 keyframes, not at the first frame";
  for (const FrameOutcome& o : outcomes)
    if (o.map_frame_fixed) {
      EXPECT_LT((o.T_map_world * outcomes.back().T_map_world.inverse()).log().norm(), 1e-12);
    }

  const std::string out = dir + "/out";
  session.writeOutputs(out, nullptr, true);
  const MapFrame written = parseMapFrameYaml(test::readFile(out + "/" + kMapFrameYaml), kMapFrameYaml);
  EXPECT_EQ(written.origin, "base");
  EXPECT_LT((written.T_map_world * outcomes.back().T_map_world.inverse()).angle(), 1e-6);
  EXPECT_LT((written.T_map_world.translation() - outcomes.back().T_map_world.translation()).norm(), 1e-6);
  const Trajectory base = readTumTrajectory(out + "/trajectory_base.txt");
  const Trajectory cam = readTumTrajectory(out + "/trajectory.txt");
  ASSERT_EQ(base.size(), cam.size());
  const SE3 expected = written.T_map_world * cam.back().T_w_c * mounting.T_b_c.inverse();
  EXPECT_LT((base.back().T_w_c.translation() - expected.translation()).norm(), 1e-4);
}

namespace {

// The vertex count a PLY header declares (-1: none).
long plyVertexCount(const std::string& path) {
  const std::string text = test::readFile(path);
  const size_t at = text.find("element vertex ");
  return at == std::string::npos ? -1 : std::stol(text.substr(at + 15));
}

struct SeenUpdate {
  int index = 0, keyframes = 0, processed = 0;
  size_t cloud = 0;
  long ply_vertices = -1;
  int grid_occupied = -1;  ///< in grid.pgm/grid.yaml as read back (-1: unreadable)
  bool refused = false;
};

}  // namespace

TEST(LiveSession, MapsGrowAndAreReadableWhileTheRunGoesOn) {
  constexpr int kFrames = 120;
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, kFrames);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const std::string scratch = test::scratchDir("session_live_maps");
  const std::string config = scratch + "/config.yaml";
  // live_nice 0: at the default 19 the maps thread may get no CPU while ctest fills both cores.
  std::ofstream(config) << "dense:\n  live_every_keyframes: 2\n  live_every_s: 0\n  live_nice: 0\n";
  RunSwitches s;
  s.sequential = true;
  s.config = config;
  SessionOptions so;
  so.drop_frames = false;
  so.maps_dir = scratch + "/out";
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<SeenUpdate> seen;  // maps thread only until stop()
  session.setMapsListener([&](const LiveMapsUpdate& u) {
    SeenUpdate v;
    v.index = u.index, v.keyframes = u.what.keyframes, v.cloud = u.cloud->size(), v.refused = u.what.refused;
    v.processed = session.counts().processed;
    // The files of this update are in place (the next one waits for this listener).
    v.ply_vertices = plyVertexCount(so.maps_dir + "/" + kDenseCloudPly);
    try {
      v.grid_occupied = readGrid(so.maps_dir + "/" + kGridYaml).count(OccupancyGrid::kOccupied);
    } catch (const std::exception&) {
    }
    seen.push_back(v);
  });
  session.start();
  TumDataset dataset = TumDataset::open(folder, camera);
  RgbdFrame frame;
  while (dataset.next(&frame)) {
    session.push(deepCopy(frame));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a camera's pace, roughly: the maps keep up
  }
  session.stop();

  ASSERT_GE(seen.size(), 3u) << "keyframes: " << session.system().map().keyframes().size();
  EXPECT_LT(seen.front().processed, kFrames) << "the first maps came while the run went on";
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].index, static_cast<int>(i + 1));
    EXPECT_EQ(seen[i].ply_vertices, static_cast<long>(seen[i].cloud)) << "update " << i + 1;
    EXPECT_GT(seen[i].grid_occupied, 0) << "update " << i + 1;
    if (i == 0) continue;
    EXPECT_GT(seen[i].keyframes, seen[i - 1].keyframes) << "update " << i + 1;
  }
  EXPECT_GT(seen.back().cloud, seen.front().cloud);
  ASSERT_NE(session.liveMaps(), nullptr);
  EXPECT_EQ(session.liveMaps()->stats().updates, static_cast<int>(seen.size()));

  // The final products are written in the frame the maps while running settled on.
  const std::optional<MapFrame> settled = session.liveMaps()->settledFrame();
  ASSERT_TRUE(settled.has_value()) << "the static scene's floor is found";
  session.writeOutputs(scratch + "/final", nullptr, true);
  const MapFrame final_frame = parseMapFrameYaml(test::readFile(scratch + "/final/" + kMapFrameYaml), kMapFrameYaml);
  EXPECT_LT((final_frame.T_map_world.translation() - settled->T_map_world.translation()).norm(), 1e-6);
  EXPECT_NE(test::readFile(scratch + "/final/stats.json").find("\"live_map_updates\""), std::string::npos);
}

// After a loop correction the next outcome carries every tracked pose so far, corrected,
// so that a front end can redraw its path (the ROS node's ~path).
TEST(LiveSession, OutcomeAfterALoopCorrectionCarriesTheRevisedTrajectory) {
  const std::string folder = test::syntheticSequence(synth::SceneKind::kLoop, 450);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const std::string config = test::scratchDir("session_revised") + "/config.yaml";
  std::ofstream(config) << "dense:\n  enabled: false\n";  // not needed here: quicker
  RunSwitches s;
  s.sequential = true;
  s.config = config;
  SessionOptions so;
  so.drop_frames = false;
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<FrameOutcome> outcomes;
  session.setFrameListener([&](const FrameOutcome& f) { outcomes.push_back(f); });
  session.start();
  TumDataset dataset = TumDataset::open(folder, camera);
  RgbdFrame frame;
  while (dataset.next(&frame)) session.push(deepCopy(frame));
  session.stop();

  ASSERT_GE(session.system().map().corrections(), 1u) << "the loop scene closes its loop";
  size_t first = outcomes.size();
  int revisions = 0, tracked = 0;
  for (size_t i = 0; i < outcomes.size(); ++i) {
    tracked += outcomes[i].tracked;
    if (!outcomes[i].revised) continue;
    ++revisions;
    if (first == outcomes.size()) first = i;
    EXPECT_EQ(outcomes[i].revised->size(), static_cast<size_t>(tracked)) << "every tracked frame so far, at " << i;
  }
  // One revision per frame that followed corrections (a loop may count several; the end's
  // finish() may add one no frame followed).
  EXPECT_GE(revisions, 1);
  EXPECT_LE(revisions, static_cast<int>(session.system().map().corrections()));
  ASSERT_LT(first, outcomes.size());
  // The revised poses are the corrected ones: they moved from what the outcomes said.
  const Trajectory& revised = *outcomes[first].revised;
  std::map<TimeNs, SE3> told;
  for (size_t i = 0; i < first; ++i)
    if (outcomes[i].tracked) told[outcomes[i].t_ns] = outcomes[i].T_w_c;
  double moved = 0;
  for (const StampedPose& p : revised)
    if (told.count(p.t_ns)) moved = std::max(moved, (told[p.t_ns].translation() - p.T_w_c.translation()).norm());
  EXPECT_GT(moved, 1e-3);
}

namespace {

// Pushes `frames` and returns once the session has processed `until` frames in all.
void pushAndWait(LiveSession* session, const std::vector<RgbdFrame>& frames, int until) {
  for (const RgbdFrame& f : frames) session->push(deepCopy(f));
  while (session->counts().processed < until) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

std::vector<RgbdFrame> sequenceFrames(const std::string& folder, const PinholeCamera& camera) {
  TumDataset dataset = TumDataset::open(folder, camera);
  std::vector<RgbdFrame> frames;
  for (RgbdFrame frame; dataset.next(&frame);) frames.push_back(deepCopy(frame));
  return frames;
}

}  // namespace

// reset() drops the map: the next frame starts a new one (its keyframe count starts again,
// its world is that frame's camera), and the outputs hold only what came after the reset.
TEST(LiveSession, ResetStartsANewMapFromTheNextFrame) {
  constexpr int kBefore = 30, kAfter = 30;
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, kBefore + kAfter);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const std::vector<RgbdFrame> frames = sequenceFrames(folder, camera);
  RunSwitches s;
  s.sequential = true;
  SessionOptions so;
  so.drop_frames = false;
  so.live_maps = false;
  so.map_frame_keyframes = 2;
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<FrameOutcome> outcomes;
  session.setFrameListener([&](const FrameOutcome& f) { outcomes.push_back(f); });
  EXPECT_THROW(session.reset(), Error) << "not running yet";
  session.start();
  pushAndWait(&session, {frames.begin(), frames.begin() + kBefore}, kBefore);
  const FrameOutcome before = outcomes.back();
  ASSERT_TRUE(before.tracked);
  ASSERT_TRUE(before.map_frame_fixed);
  ASSERT_GE(before.keyframes, 3);
  const size_t keyframes_before = session.system().map().keyframes().size();
  session.reset();
  EXPECT_FALSE(session.mapFrame().has_value()) << "the map frame goes with the map";
  EXPECT_TRUE(session.sparseMap().points.empty());
  pushAndWait(&session, {frames.begin() + kBefore, frames.end()}, kBefore + kAfter);
  session.stop();

  ASSERT_EQ(outcomes.size(), static_cast<size_t>(kBefore + kAfter));
  const FrameOutcome& first = outcomes[kBefore];
  EXPECT_EQ(before.resets, 0);
  EXPECT_EQ(first.resets, 1);
  ASSERT_TRUE(first.tracked) << first.reason;
  EXPECT_EQ(first.keyframes, 1) << "the first frame after the reset makes the new map's first keyframe";
  EXPECT_FALSE(first.map_frame_fixed) << "fixed anew from the new map";
  // The new world is the camera of the first frame after the reset, which had moved.
  EXPECT_LT(first.T_w_c.log().norm(), 1e-9);
  EXPECT_GT(before.T_w_c.translation().norm(), 0.05);
  EXPECT_TRUE(outcomes.back().map_frame_fixed);
  EXPECT_LT(outcomes.back().keyframes, before.keyframes + static_cast<int>(keyframes_before));

  // The outputs are the new map's: its keyframes and its poses, all from after the reset.
  const TimeNs reset_at = frames[kBefore].t_ns;
  const Trajectory trajectory = session.system().trajectory();
  EXPECT_EQ(trajectory.size(), static_cast<size_t>(session.counts().tracked) - kBefore);
  for (const StampedPose& p : trajectory) EXPECT_GE(p.t_ns, reset_at);
  for (const auto& [id, kf] : session.system().map().keyframes()) EXPECT_GE(kf.t_ns, reset_at);
  const std::string out = test::scratchDir("session_reset") + "/out";
  session.writeOutputs(out, nullptr, false);
  const Trajectory written = readTumTrajectory(out + "/trajectory.txt");
  ASSERT_EQ(written.size(), trajectory.size());
  EXPECT_EQ(written.front().t_ns, reset_at);
  EXPECT_EQ(session.counts().received, kBefore + kAfter) << "the counts are the session's, across the reset";
}

namespace {

struct MapSize {
  size_t keyframes = 0, points = 0, lines = 0;
  bool operator==(const MapSize& o) const { return keyframes == o.keyframes && points == o.points && lines == o.lines; }
};

MapSize mapSize(const LiveSession& session) {
  const Map& map = session.system().map();
  std::lock_guard<std::mutex> lock(map.mutex());
  return {map.keyframes().size(), map.points().size(), map.lines().size()};
}

}  // namespace

// setLocalization(true) keeps the map as it is (no keyframe, no landmark added or culled)
// while the frames are still tracked in it; setLocalization(false) maps again.
TEST(LiveSession, LocalizationKeepsTheMapAndStillTracks) {
  constexpr int kPart = 30;
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 3 * kPart);
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const std::vector<RgbdFrame> frames = sequenceFrames(folder, camera);
  RunSwitches s;
  s.sequential = true;
  SessionOptions so;
  so.drop_frames = false;
  so.live_maps = false;
  LiveSession session(camera, makeRunConfig(s, "test"), so);
  std::vector<FrameOutcome> outcomes;
  session.setFrameListener([&](const FrameOutcome& f) { outcomes.push_back(f); });
  session.start();
  auto part = [&](int i) { return std::vector<RgbdFrame>(frames.begin() + i * kPart, frames.begin() + (i + 1) * kPart); };
  pushAndWait(&session, part(0), kPart);
  const MapSize mapped = mapSize(session);
  ASSERT_GE(mapped.keyframes, 2u);
  session.setLocalization(true);
  EXPECT_TRUE(session.localizing());
  pushAndWait(&session, part(1), 2 * kPart);
  const MapSize localised = mapSize(session);
  EXPECT_TRUE(localised == mapped) << "keyframes " << mapped.keyframes << " -> " << localised.keyframes << ", points "
                                   << mapped.points << " -> " << localised.points;
  int tracked = 0;
  for (int i = kPart; i < 2 * kPart; ++i) {
    tracked += outcomes[i].tracked;
    EXPECT_EQ(outcomes[i].keyframes, outcomes[kPart - 1].keyframes) << i;
  }
  EXPECT_EQ(tracked, kPart) << "every frame is still tracked while localising";
  session.setLocalization(false);
  EXPECT_FALSE(session.localizing());
  pushAndWait(&session, part(2), 3 * kPart);
  session.stop();
  EXPECT_GT(mapSize(session).keyframes, mapped.keyframes) << "mapping again";
  EXPECT_EQ(session.system().trajectory().size(), static_cast<size_t>(session.counts().tracked));
}
