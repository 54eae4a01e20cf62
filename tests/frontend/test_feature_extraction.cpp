#include <gtest/gtest.h>

#include "core/worker_thread.h"
#include "frontend/feature_extraction.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam {
namespace {

void expectSameFeatures(const FrameFeatures& a, const FrameFeatures& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].uv_raw, b.points[i].uv_raw);
    EXPECT_EQ(a.points[i].angle, b.points[i].angle);
    EXPECT_EQ(a.points[i].octave, b.points[i].octave);
  }
  EXPECT_EQ(cv::norm(a.point_descriptors, b.point_descriptors, cv::NORM_HAMMING), 0.0);
  ASSERT_EQ(a.lines.size(), b.lines.size());
  for (size_t i = 0; i < a.lines.size(); ++i) {
    EXPECT_EQ(a.lines[i].p_raw, b.lines[i].p_raw);
    EXPECT_EQ(a.lines[i].q_raw, b.lines[i].q_raw);
  }
  EXPECT_EQ(cv::norm(a.line_descriptors, b.line_descriptors, cv::NORM_HAMMING), 0.0);
}

TEST(FeatureExtraction, TheWorkerThreadsShareDoesNotChangeTheFeatures) {
  // With a worker, the coarse pyramid levels' FAST corners and the segments run on it; on one
  // thread everything runs in order. Both give the same features, frame after frame.
  const PinholeCamera camera = synth::syntheticCamera(640, 480);
  synth::SceneOptions so;
  so.frames = 4;
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, so);
  WorkerThread worker("test-features");
  FeatureOptions in_order;
  in_order.parallel = false;
  const FeatureOptions parallel;
  for (int i = 0; i < so.frames; ++i) {
    const RgbdFrame frame = synth::render(scene, i).toRgbdFrame();
    const FrameFeatures alone = extractFeatures(frame, cv::Mat(), camera, in_order);
    ASSERT_GT(alone.points.size(), 300u);
    ASSERT_GT(alone.lines.size(), 10u);
    FeatureExtraction extraction(frame, cv::Mat(), camera, parallel, &worker);
    StageTimes times;
    FrameFeatures shared = extraction.points(&times);
    extraction.addLines(&shared, &times);
    expectSameFeatures(alone, shared);
    EXPECT_GT(times[Stage::kOrbDetect], 0.0);
    EXPECT_GT(times[Stage::kLsd], 0.0);
  }
}

}  // namespace
}  // namespace plslam
