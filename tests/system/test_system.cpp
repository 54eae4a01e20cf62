// The whole pipeline on synthetic scenes with exact ground truth, on broken input, and on
// the real TUM sequences of ../shared (regression thresholds, skipped without it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "camera/camera_file.h"
#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "io/dataset.h"
#include "support/test_support.h"
#include "synthetic_cache.h"
#include "core/option_table.h"
#include "system/run_outputs.h"
#include "system/system.h"

using namespace plslam;

namespace {

struct RunResult {
  Trajectory trajectory;
  RunStats stats;
  double ate = NAN;
};

RunResult runOn(const std::string& dir, const PinholeCamera& camera, SystemOptions options) {
  TumDataset data = TumDataset::open(dir, camera);
  System slam(camera, options);
  slam.start();
  RgbdFrame frame;
  while (data.next(&frame)) slam.feed(frame);
  slam.finish();
  RunResult r;
  r.trajectory = slam.trajectory();
  r.stats = slam.stats();
  if (data.hasGroundtruth() && r.trajectory.size() >= 3) r.ate = evaluate(data.groundtruth(), r.trajectory).ate.stats.rmse;
  return r;
}

SystemOptions sequential() {
  SystemOptions o;
  o.sequential = true;
  return o;
}

}  // namespace

TEST(SystemSynthetic, StaticSceneWithinFiveMillimetresAndDeterministic) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  const RunResult a = runOn(dir, camera, sequential());
  EXPECT_EQ(a.stats.tracked, a.stats.frames);
  EXPECT_EQ(a.stats.lost_events, 0);
  EXPECT_LT(a.ate, 0.005) << "ATE RMSE on the synthetic static scene";
  EXPECT_GT(a.stats.map_lines, 20) << "lines should be mapped on a scene full of edges";
  const RunResult b = runOn(dir, camera, sequential());
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  for (size_t i = 0; i < a.trajectory.size(); ++i) {
    ASSERT_EQ(a.trajectory[i].t_ns, b.trajectory[i].t_ns);
    ASSERT_EQ(a.trajectory[i].T_w_c.matrix(), b.trajectory[i].T_w_c.matrix()) << "sequential runs differ at pose " << i;
  }
}

TEST(SystemSynthetic, FrameRefinementBringsTheTrajectoryCloserToTheTruth) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  SystemOptions as_tracked = sequential();
  as_tracked.refine_frames = false;
  const RunResult a = runOn(dir, camera, as_tracked);
  const RunResult b = runOn(dir, camera, sequential());
  std::printf("static scene ATE: as tracked %.5f m, refined %.5f m (%d of %d frames refined)\n", a.ate, b.ate,
              b.stats.refined_frames, b.stats.tracked);
  EXPECT_EQ(a.stats.refined_frames, 0);
  EXPECT_GE(b.stats.refined_frames, b.stats.tracked * 9 / 10) << "nearly every tracked frame has matches to refine with";
  EXPECT_LT(b.ate, a.ate);
}

TEST(SystemSynthetic, ANegativeRefinementDelayIsAConfigError) {
  const PinholeCamera camera = synth::syntheticCamera(640, 480);
  SystemOptions o = sequential();
  o.refine_after_frames = -1;
  EXPECT_THROW(System(camera, o), ConfigError);
  o.refine_after_frames = 300;
  o.refine_after_keyframes = -2;
  EXPECT_THROW(System(camera, o), ConfigError);
  o.refine_after_keyframes = 0;  // refine as soon as possible: allowed
  EXPECT_NO_THROW(System(camera, o));
}

TEST(SystemSynthetic, MapperAndLoopOptionsOutOfRangeAreRefusedByTheirKeys) {
  const PinholeCamera camera = synth::syntheticCamera(320, 240);
  auto refused = [&](auto change, const std::string& key) {
    SystemOptions o = sequential();
    o.use_loop = true;
    change(&o);
    try {
      System slam(camera, o);
      ADD_FAILURE() << key << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  refused([](SystemOptions* o) { o->mapper.ba_keyframes = 0; }, "mapper.ba_keyframes");
  refused([](SystemOptions* o) { o->mapper.cull_found_ratio = 1.5; }, "mapper.cull_found_ratio");
  refused([](SystemOptions* o) { o->mapper.cull_single_after = 0; }, "mapper.cull_single_after");
  refused([](SystemOptions* o) { o->mapper.ba.max_time_s = -1; }, "mapper.ba_max_time_s");
  refused([](SystemOptions* o) { o->loop.consistency = 0; }, "loop.consistency");
  refused([](SystemOptions* o) { o->loop.min_inlier_ratio = 2; }, "loop.min_inlier_ratio");
  refused([](SystemOptions* o) { o->loop.edge_sigma_rot_deg = 0; }, "loop.edge_sigma_rot_deg");
  refused([](SystemOptions* o) { o->loop.point_weight = o->loop.line_weight = 0; }, "loop.point_weight");
  SystemOptions fine = sequential();
  fine.use_loop = true;
  EXPECT_NO_THROW(System(camera, fine));
}

TEST(SystemSynthetic, LoopAndMapperConstantsAreConfigKeys) {
  // Fields that had no key (issue 21): each key reaches its field.
  SystemOptions o;
  OptionTable table;
  bindOptions(&table, &o);
  table.set("loop.global_ba", "false", "test.yaml");
  table.set("loop.global_ba_max_time_s", "1.5", "test.yaml");
  table.set("loop.min_keyframes_between_loops", "9", "test.yaml");
  table.set("loop.covisibility_edge_min_shared", "70", "test.yaml");
  table.set("loop.covisible_exclude_min_shared", "4", "test.yaml");
  table.set("loop.line_max_distance", "90", "test.yaml");
  table.set("loop.max_depth_m", "4.5", "test.yaml");
  table.set("mapper.cull_min_visible", "8", "test.yaml");
  table.set("mapper.min_covisible_points", "20", "test.yaml");
  EXPECT_FALSE(o.loop.global_ba);
  EXPECT_EQ(o.loop.ba.max_time_s, 1.5);
  EXPECT_EQ(o.loop.min_keyframes_between_loops, 9);
  EXPECT_EQ(o.loop.covisibility_edge_min_shared, 70);
  EXPECT_EQ(o.loop.covisible_exclude_min_shared, 4);
  EXPECT_EQ(o.loop.line_max_distance, 90);
  EXPECT_EQ(o.loop.max_depth_m, 4.5);
  EXPECT_EQ(o.mapper.cull_min_visible, 8);
  EXPECT_EQ(o.mapper.min_covisible_points, 20);
}

TEST(SystemSynthetic, ThreadedModeTracksAndFinishes) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  SystemOptions threaded;
  threaded.sequential = false;
  const RunResult r = runOn(dir, camera, threaded);
  EXPECT_EQ(r.stats.tracked, r.stats.frames);
  // Threaded runs measured 0.0026-0.0030 m (5 quiet, 3 with both cores loaded by `yes`);
  // sequential 0.0029 m. The bound leaves room for the mapping thread's timing, no more.
  std::printf("threaded synthetic static: ATE RMSE %.4f m\n", r.ate);
  EXPECT_LT(r.ate, 0.004);
  EXPECT_GT(r.stats.keyframes, 2);
}

// On a revisit (the keyframe sharing the most landmarks with the frame is older than the
// local_keyframes newest) a keyframe is made only when the frame tracks weakly or moved away
// from that keyframe, not by time, so that the map grows less where nothing new is seen
// (issue 16: a long run's tracking time and memory). Without that rule the second lap made
// as many keyframes as the first (33 against 34); with it 13, hence the bound of half.
TEST(SystemSynthetic, ASecondLapOfTheRoomAddsFewKeyframes) {
  synth::SceneOptions so;
  so.width = 320;
  so.height = 240;
  so.frames = 600;
  so.laps = 2;
  const test::RenderedSequence seq = test::renderSequence(synth::SceneKind::kLoop, so);
  SystemOptions o = sequential();
  o.dense.enabled = false;
  System slam(seq.scene.camera(), o);
  slam.start();
  int first_lap = 0, second_lap = 0, tracked = 0;
  for (size_t k = 0; k < seq.frames.size(); ++k) {
    const TrackingResult r = slam.feed(seq.frames[k].toRgbdFrame());
    tracked += r.status == TrackingStatus::kOk || r.status == TrackingStatus::kInitialized;
    if (r.new_keyframe) ++(k < seq.frames.size() / 2 ? first_lap : second_lap);
  }
  slam.finish();
  std::printf("[figures] keyframes made: first lap %d, second lap %d; %d of %zu frames tracked; loops closed %d\n",
              first_lap, second_lap, tracked, seq.frames.size(), slam.stats().loop.accepted);
  EXPECT_EQ(tracked, static_cast<int>(seq.frames.size()));
  EXPECT_GE(first_lap, 15);
  EXPECT_LE(second_lap, first_lap / 2);
  const double ate = evaluate(seq.scene.groundTruth(), slam.trajectory()).ate.stats.rmse;
  EXPECT_LT(ate, 0.02);
}

TEST(SystemSynthetic, PointsOnlyStillTracks) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  SystemOptions o = sequential();
  o.use_lines = false;
  const RunResult r = runOn(dir, camera, o);
  EXPECT_EQ(r.stats.map_lines, 0);
  EXPECT_EQ(r.stats.tracked, r.stats.frames);
  EXPECT_LT(r.ate, 0.01);
  // The profile says where the time went: no line stage ran.
  for (Stage st : {Stage::kLsd, Stage::kLineMerge, Stage::kLbd})
    for (double ms : r.stats.stage_ms[static_cast<int>(st)]) EXPECT_EQ(ms, 0.0) << stageName(st);
}

TEST(SystemSynthetic, EveryTrackedFrameHasATimeForEachStageThatRan) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  SystemOptions threaded;  // the mode a robot runs: points and lines on two threads
  threaded.sequential = false;
  const RunResult r = runOn(dir, camera, threaded);
  ASSERT_EQ(r.stats.tracked, r.stats.frames);
  for (int i = 0; i < kStageCount; ++i) ASSERT_EQ(r.stats.stage_ms[i].size(), static_cast<size_t>(r.stats.frames));
  // Every frame is extracted and checked; every frame but the first (which initialises the
  // map) is searched for and optimised.
  for (Stage st : {Stage::kOrbDetect, Stage::kOrbDescribe, Stage::kLsd, Stage::kLineMerge, Stage::kLbd, Stage::kUndistort,
                   Stage::kDynamic})
    for (double ms : r.stats.stage_ms[static_cast<int>(st)]) EXPECT_GT(ms, 0.0) << stageName(st);
  for (Stage st : {Stage::kSearch, Stage::kPoseOptimisation})
    for (size_t f = 1; f < r.stats.stage_ms[static_cast<int>(st)].size(); ++f)
      EXPECT_GT(r.stats.stage_ms[static_cast<int>(st)][f], 0.0) << stageName(st) << " of frame " << f;
}

TEST(SystemSynthetic, EachSearchedFrameRecordsItsLocalMapSizeInFramesCsv) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  TumDataset data = TumDataset::open(dir, camera);
  System slam(camera, sequential());
  slam.start();
  RgbdFrame frame;
  while (data.next(&frame)) slam.feed(frame);
  slam.finish();
  const std::vector<FrameRecord>& records = slam.records();
  ASSERT_GT(records.size(), 2u);
  EXPECT_EQ(records[0].local_points, 0) << "the first frame starts the map: nothing was searched";
  for (size_t f = 1; f < records.size(); ++f) {
    EXPECT_GT(records[f].local_points, 0) << "frame " << f;
    EXPECT_GT(records[f].local_lines, 0) << "frame " << f;
    // What a frame matched came out of the local map it searched.
    EXPECT_GE(records[f].local_points, records[f].matched_points) << "frame " << f;
  }
  // frames.csv ends each line with the two counts.
  const std::string csv = framesToCsv(records);
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.substr(header.size() - std::string(",local_points,local_lines").size()), ",local_points,local_lines");
  const std::string last_row_end =
      "," + std::to_string(records.back().local_points) + "," + std::to_string(records.back().local_lines) + "\n";
  EXPECT_EQ(csv.substr(csv.size() - last_row_end.size()), last_row_end);
}

TEST(SystemRobustness, FramesWithoutDepthOrTextureGiveAStatusNotACrash) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  TumDataset data = TumDataset::open(dir, camera);
  System slam(camera, sequential());
  slam.start();

  RgbdFrame blank;
  blank.t_ns = 1;
  blank.bgr = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(90, 90, 90));
  blank.depth_m = cv::Mat(camera.height, camera.width, CV_32F, cv::Scalar(NAN));
  TrackingResult r = slam.feed(blank);
  EXPECT_EQ(r.status, TrackingStatus::kNotInitialized);
  EXPECT_FALSE(r.reason.empty());

  RgbdFrame frame;
  ASSERT_TRUE(data.next(&frame));
  RgbdFrame no_depth = frame;
  no_depth.depth_m = cv::Mat(camera.height, camera.width, CV_32F, cv::Scalar(NAN));
  EXPECT_EQ(slam.feed(no_depth).status, TrackingStatus::kNotInitialized) << "textured but no depth: cannot initialise";
  EXPECT_EQ(slam.feed(frame).status, TrackingStatus::kInitialized);

  blank.t_ns = frame.t_ns + 1000;
  r = slam.feed(blank);
  EXPECT_FALSE(isTracked(r.status));
  EXPECT_FALSE(r.reason.empty());
  RgbdFrame empty;
  empty.t_ns = blank.t_ns + 1000;
  EXPECT_FALSE(isTracked(slam.feed(empty).status));

  // Back to real frames: relocalisation finds the map again.
  int tracked = 0;
  for (int i = 0; i < 10 && data.next(&frame); ++i) tracked += isTracked(slam.feed(frame).status);
  EXPECT_GE(tracked, 8);
  slam.finish();
  EXPECT_EQ(slam.stats().lost_events, 1);
  EXPECT_GE(slam.stats().relocalisations, 1);
  EXPECT_THROW(slam.feed(frame), Error);
}

namespace {
void expectTumRegression(const std::string& sequence, const std::string& calib, double max_ate, bool all_tracked,
                         SystemOptions options = sequential()) {
  const std::string dir = test::sharedDir() + "/data/tum/" + sequence;
  const PinholeCamera camera = loadCameraFile(test::sourceDir() + "/calib/" + calib);
  const RunResult r = runOn(dir, camera, options);
  std::printf("%s: ATE RMSE %.4f m, tracked %d/%d, keyframes %d, line rate fitting %.3f endpoints %.3f\n",
              sequence.c_str(), r.ate, r.stats.tracked, r.stats.frames, r.stats.keyframes, r.stats.line_rate_fitting,
              r.stats.line_rate_endpoints);
  EXPECT_LE(r.ate, max_ate);
  if (all_tracked) {
    EXPECT_EQ(r.stats.tracked, r.stats.frames);
  }
  EXPECT_GT(r.stats.line_rate_fitting, r.stats.line_rate_endpoints) << "fitting should build more 3D lines";
}
}  // namespace

TEST(TumRegression, Fr1XyzAteAndTracking) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr1_xyz_0-199");
  // Bounds about 10 % above the measured figure (docs/RESULTS.md, accuracy table).
  expectTumRegression("fr1_xyz_0-199", "tum_freiburg1.xml", 0.0115, true);
}

TEST(TumRegression, Fr3SittingStaticAte) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr3_sitting_static_150");
  expectTumRegression("fr3_sitting_static_150", "tum_freiburg3.xml", 0.011, false);
}

TEST(TumRegression, Fr3SittingStaticWithYoloMasksAte) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr3_sitting_static_150");
  PLSLAM_REQUIRE_SHARED("models/yolov8n-seg-320.onnx");
  SystemOptions o = sequential();
  o.segmenter.kind = SegmenterKind::kYolo;
  o.segmenter.yolo.model_path = test::sharedDir() + "/models/yolov8n-seg-320.onnx";
  // Published on the whole sequence: ORB-SLAM2 0.0087, DS-SLAM 0.0065. Figures in docs/RESULTS.md.
  expectTumRegression("fr3_sitting_static_150", "tum_freiburg3.xml", 0.0073, true, o);
}

TEST(SystemThreads, AMappingThreadFailureStopsThePipelineAndIsRethrownNamingTheThread) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  SystemOptions threaded;
  threaded.sequential = false;
  System slam(camera, threaded);
  int mapped = 0;
  slam.setKeyframeObserver([&mapped](Id) {
    if (++mapped == 2) throw std::runtime_error("injected failure");
  });
  slam.start();
  TumDataset data = TumDataset::open(dir, camera);
  RgbdFrame frame;
  std::string message;
  size_t fed = 0;
  try {
    while (data.next(&frame)) slam.feed(frame), ++fed;
    slam.finish();
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("mapping thread failed: injected failure"), std::string::npos) << message;
  EXPECT_EQ(mapped, 2) << "no keyframe is mapped after the failure";
  EXPECT_GE(slam.records().size(), fed) << "what was tracked before the failure stays readable";
  EXPECT_THROW(slam.finish(), Error) << "finish() after the failure says it again";
}

TEST(SystemThreads, AnObserverFailureInSequentialModeComesOutOfFeed) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  System slam(camera, sequential());
  slam.setKeyframeObserver([](Id) { throw std::runtime_error("injected failure"); });
  slam.start();
  TumDataset data = TumDataset::open(dir, camera);
  RgbdFrame frame;
  ASSERT_TRUE(data.next(&frame));
  EXPECT_THROW(slam.feed(frame), std::runtime_error) << "the first frame makes the first keyframe";
}
