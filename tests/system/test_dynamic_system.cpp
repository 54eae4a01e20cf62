// Moving persons must neither drag the pose nor leave landmarks in the map.
#include <gtest/gtest.h>

#include "camera/camera_file.h"
#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "io/dataset.h"
#include "support/test_support.h"
#include <cmath>
#include <functional>
#include <map>

#include "synth/scene.h"
#include "synthetic_cache.h"
#include "system/system.h"

using namespace plslam;

namespace {

struct DynamicRun {
  int landmarks_on_persons = 0;
  int landmarks = 0;
  double ate = 0;
  int keyframe_instances = 0, keyframe_instances_dynamic = 0;
  RunStats stats;
};

// Runs the synthetic dynamic scene and counts, over all keyframes, the keypoints with depth
// on a person's pixels (exact instance masks of the renderer): each became a map point when
// its keyframe was made. (Counting the final map's points would hide them: culling and
// bundle adjustment drop most of them later, which is not the same as never using them.)
DynamicRun runDynamicScene(bool reject, SegmenterKind segmenter, synth::SceneKind scene = synth::SceneKind::kDynamic,
                           int frames = 120, const std::function<void(SystemOptions*)>& adjust = {}) {
  const std::string dir = test::syntheticSequence(scene, frames);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  TumDataset data = TumDataset::open(dir, camera);
  SystemOptions options;
  options.sequential = true;
  options.dynamic.enabled = reject;
  options.dynamic.segment_every = 1;
  options.segmenter.kind = segmenter;
  if (adjust) adjust(&options);
  for (const InstanceLabel& l : data.instanceLabels())
    options.segmenter.replay_labels.push_back({l.instance_id, l.class_id, l.class_name});
  System slam(camera, options);
  slam.start();
  std::map<TimeNs, cv::Mat> person_masks;
  RgbdFrame frame;
  while (data.next(&frame)) {
    person_masks[frame.t_ns] = frame.instance_ids;
    slam.feed(frame);
  }
  slam.finish();
  DynamicRun r;
  r.stats = slam.stats();
  r.ate = evaluate(data.groundtruth(), slam.trajectory()).ate.stats.rmse;
  for (const auto& [id, kf] : slam.map().keyframes()) {
    const cv::Mat& ids = person_masks.at(kf.t_ns);
    r.keyframe_instances += static_cast<int>(kf.instances.size());
    for (const KeyframeInstance& in : kf.instances) r.keyframe_instances_dynamic += in.dynamic;
    for (const Keypoint& k : kf.features.points) {
      if (!std::isfinite(k.depth_m)) continue;
      ++r.landmarks;
      const Eigen::Vector2d& uv = k.uv_raw;
      r.landmarks_on_persons += ids.at<uint16_t>(static_cast<int>(uv.y()), static_cast<int>(uv.x())) != 0;
    }
  }
  return r;
}

}  // namespace

TEST(DynamicSystem, NoPersonLandmarksEnterTheMapWithReplayedMasks) {
  const DynamicRun on = runDynamicScene(true, SegmenterKind::kReplay);
  const DynamicRun off = runDynamicScene(false, SegmenterKind::kNone);
  std::printf("keyframe landmarks on persons: %d of %d with rejection, %d of %d without; ATE %.4f vs %.4f m\n",
              on.landmarks_on_persons, on.landmarks, off.landmarks_on_persons, off.landmarks, on.ate, off.ate);
  EXPECT_GT(off.landmarks_on_persons, 0) << "the scene must put persons in view for this test to mean anything";
  EXPECT_EQ(on.landmarks_on_persons, 0);
  EXPECT_EQ(on.stats.tracked, on.stats.frames);
  EXPECT_LT(on.ate, 0.01);
  double rejected = 0;
  for (double v : on.stats.dynamic_points_rejected) rejected += v;
  EXPECT_GT(rejected, 0);
  // The keyframes keep the instances they saw, the walking persons marked dynamic.
  EXPECT_GT(on.keyframe_instances_dynamic, 0);
  EXPECT_EQ(off.keyframe_instances, 0);
}

TEST(DynamicSystem, GeometryAloneRemovesMostPersonLandmarks) {
  const DynamicRun geo = runDynamicScene(true, SegmenterKind::kNone);
  const DynamicRun off = runDynamicScene(false, SegmenterKind::kNone);
  std::printf("landmarks on persons: %d geometry only, %d without rejection\n", geo.landmarks_on_persons,
              off.landmarks_on_persons);
  ASSERT_GT(off.landmarks_on_persons, 100) << "the scene must put persons in view for this test to mean anything";
  // "Most": at least four in five of them kept out (measured: 93 of 806 left, 88 % out).
  EXPECT_LE(geo.landmarks_on_persons, 0.2 * off.landmarks_on_persons);
  EXPECT_EQ(geo.stats.tracked, geo.stats.frames);
}

// Persons cover more than half of the view for a stretch (issue 4: all frames tracked, ATE at
// most 0.02 m; lines on the background carry the pose while points are scarce).
TEST(DynamicSystem, CrowdedSceneIsTrackedWithReplayedMasks) {
  const DynamicRun rep = runDynamicScene(true, SegmenterKind::kReplay, synth::SceneKind::kCrowded, 300);
  std::printf("crowded scene, 300 frames, replayed masks: ATE %.4f m (%d/%d tracked)\n", rep.ate, rep.stats.tracked,
              rep.stats.frames);
  EXPECT_EQ(rep.stats.tracked, rep.stats.frames);
  EXPECT_LT(rep.ate, 0.02);
}

// The first passage of the crowd, without masks: the geometric checks alone keep the persons
// out of the pose. (Over the whole 300 frames geometry alone is not enough yet: near frame 213
// the tracker's motion prior follows a walker and the check, constrained by it, then confirms
// the walker: 0.08 m.)
TEST(DynamicSystem, CrowdedSceneFirstPassageIsTrackedByGeometryAlone) {
  const DynamicRun geo = runDynamicScene(true, SegmenterKind::kNone, synth::SceneKind::kCrowded, 150);
  const DynamicRun off = runDynamicScene(false, SegmenterKind::kNone, synth::SceneKind::kCrowded, 150);
  std::printf("crowded scene, 150 frames: ATE %.4f m geometry only (%d/%d tracked), %.4f m without rejection\n", geo.ate,
              geo.stats.tracked, geo.stats.frames, off.ate);
  EXPECT_EQ(geo.stats.tracked, geo.stats.frames);
  EXPECT_LT(geo.ate, 0.02);
  EXPECT_GT(off.ate, 3 * geo.ate) << "the scene must be one the persons spoil without rejection";
}

// Masks delivered 4 frames late (dynamic.replay_latency_frames), the crowded scene: the
// stale-mask failure is reproduced (the walkers drag the pose), and masks carried to the frame
// avoid it.
TEST(DynamicSystem, CrowdedSceneWithMasksFourFramesLateIsTrackedWhenTheyAreCarried) {
  DynamicRun runs[2];
  for (const bool propagate : {false, true})
    runs[propagate] = runDynamicScene(true, SegmenterKind::kReplay, synth::SceneKind::kCrowded, 300, [&](SystemOptions* o) {
      o->dynamic.latency_frames = 4;
      o->dynamic.propagate_masks = propagate;
    });
  std::printf("crowded scene, masks 4 frames late: ATE %.4f m stale (%d/%d tracked), %.4f m carried (%d/%d)\n",
              runs[0].ate, runs[0].stats.tracked, runs[0].stats.frames, runs[1].ate, runs[1].stats.tracked,
              runs[1].stats.frames);
  for (const DynamicRun& r : runs) {
    ASSERT_EQ(r.stats.mask_age_frames.size(), 300u);
    for (size_t i = 4; i < r.stats.mask_age_frames.size(); ++i) ASSERT_EQ(r.stats.mask_age_frames[i], 4) << "frame " << i;
  }
  EXPECT_EQ(runs[1].stats.tracked, runs[1].stats.frames);
  EXPECT_LT(runs[1].ate, 0.02);
  EXPECT_GT(runs[0].ate, 2 * runs[1].ate) << "the latency must reproduce the stale-mask failure";
}

// The threaded pipeline gives each frame the masks of exactly k frames back too.
TEST(DynamicSystem, ThreadedRunsUseMasksExactlyTheLatencyLate) {
  const DynamicRun r = runDynamicScene(true, SegmenterKind::kReplay, synth::SceneKind::kDynamic, 40, [](SystemOptions* o) {
    o->sequential = false;
    o->dynamic.latency_frames = 3;
  });
  ASSERT_EQ(r.stats.mask_age_frames.size(), 40u);
  for (size_t i = 0; i < r.stats.mask_age_frames.size(); ++i)
    EXPECT_EQ(r.stats.mask_age_frames[i], static_cast<int>(std::min<size_t>(i, 3))) << "frame " << i;
}

TEST(DynamicSystem, ANegativeMaskLatencyIsRefusedNamingTheKey) {
  SystemOptions o;
  OptionTable table;
  bindOptions(&table, &o);
  table.set("dynamic.replay_latency_frames", "-2", "test.yaml");
  try {
    System slam(synth::syntheticCamera(640, 480), o);
    FAIL() << "a negative latency was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dynamic.replay_latency_frames"), std::string::npos) << e.what();
  }
}
