// DynamicFilter's segmentation schedule and worker lifecycle: inline every N frames when
// sequential; on a worker thread, one frame at a time, results carried to later frames,
// and a destructor that waits for a busy worker instead of hanging or crashing.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "frontend/dynamic_filter.h"
#include "frontend/feature_extraction.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam {
namespace {

// The replay backend behind a delay, counting calls and how many ran at once.
class SlowSegmenter : public Segmenter {
 public:
  SlowSegmenter(std::chrono::milliseconds delay, std::atomic<int>* calls, std::atomic<int>* max_concurrent)
      : delay_(delay), calls_(calls), max_concurrent_(max_concurrent) {
    SegmenterOptions o;
    o.kind = SegmenterKind::kReplay;
    o.replay_labels = {{1, 0, "person"}, {2, 0, "person"}, {3, 0, "person"}};
    replay_ = makeSegmenter(o);
  }
  Segmentation segment(const cv::Mat& bgr, TimeNs t_ns) override { return replay_->segment(bgr, t_ns); }
  Segmentation segment(const RgbdFrame& frame) override {
    const int now = ++running_;
    int seen = max_concurrent_->load();
    while (now > seen && !max_concurrent_->compare_exchange_weak(seen, now)) {
    }
    ++*calls_;
    std::this_thread::sleep_for(delay_);
    Segmentation s = replay_->segment(frame);
    --running_;
    return s;
  }
  std::string name() const override { return "slow-replay"; }

 private:
  std::chrono::milliseconds delay_;
  std::atomic<int>* calls_;
  std::atomic<int>* max_concurrent_;
  std::atomic<int> running_{0};
  std::unique_ptr<Segmenter> replay_;
};

struct Frames {
  PinholeCamera camera = synth::syntheticCamera(640, 480);
  std::vector<synth::RenderedFrame> rendered;
  Frames() {
    synth::SceneOptions so;
    so.frames = 12;
    const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, so);
    for (int i = 0; i < so.frames; ++i) rendered.push_back(synth::render(scene, i));
  }
};

const Frames& frames() {
  static const Frames f;
  return f;
}

std::vector<DynamicFrameResult> runFilter(DynamicFilter* filter, std::chrono::milliseconds pause) {
  std::vector<DynamicFrameResult> out;
  for (const synth::RenderedFrame& r : frames().rendered) {
    const RgbdFrame frame = r.toRgbdFrame();
    FrameFeatures f = extractFeatures(frame, cv::Mat(), frames().camera, FeatureOptions{});
    out.push_back(filter->process(frame, &f, std::nullopt));
    std::this_thread::sleep_for(pause);
  }
  return out;
}

TEST(DynamicFilterSchedule, SequentialSegmentsEveryNthFrameAndAgesTheMasksInBetween) {
  std::atomic<int> calls{0}, concurrent{0};
  DynamicFilterOptions o;
  o.segment_every = 3;
  DynamicFilter filter(frames().camera, o,
                       std::make_unique<SlowSegmenter>(std::chrono::milliseconds(0), &calls, &concurrent), false);
  const std::vector<DynamicFrameResult> r = runFilter(&filter, std::chrono::milliseconds(0));
  EXPECT_EQ(calls.load(), 4);  // frames 0, 3, 6, 9
  for (size_t i = 0; i < r.size(); ++i) {
    EXPECT_EQ(r[i].mask_age_frames, static_cast<int>(i % 3)) << "frame " << i;
    EXPECT_TRUE(r[i].fresh_segmentation);
    EXPECT_EQ(r[i].segmentation_ms >= 0, i % 3 == 0) << "frame " << i;
  }
}

TEST(DynamicFilterSchedule, NoneSegmenterGivesNoMasksToAgeOrCount) {
  // Geometry-only runs: no frame has a fresh mask and no segmentation time is reported, in
  // either mode (stats.json's fresh_mask_fraction stays 0).
  for (const bool asynchronous : {false, true}) {
    DynamicFilter filter(frames().camera, DynamicFilterOptions{}, std::make_unique<NoneSegmenter>(), asynchronous);
    for (const DynamicFrameResult& r : runFilter(&filter, std::chrono::milliseconds(0))) {
      EXPECT_FALSE(r.fresh_segmentation) << (asynchronous ? "threaded" : "sequential");
      EXPECT_LT(r.segmentation_ms, 0);
      EXPECT_LT(r.mask_age_frames, 0);
    }
  }
}

TEST(DynamicFilterSchedule, WorkerSegmentsOneFrameAtATimeAndLaterFramesUseItsMasks) {
  std::atomic<int> calls{0}, concurrent{0};
  DynamicFilterOptions o;
  o.segment_every = 2;
  DynamicFilter filter(frames().camera, o,
                       std::make_unique<SlowSegmenter>(std::chrono::milliseconds(60), &calls, &concurrent), true);
  const std::vector<DynamicFrameResult> r = runFilter(&filter, std::chrono::milliseconds(20));
  EXPECT_EQ(concurrent.load(), 1);
  EXPECT_GE(calls.load(), 2);
  EXPECT_LE(calls.load(), 6);  // at most every second frame
  int arrivals = 0;
  bool have_masks = false;
  for (size_t i = 0; i < r.size(); ++i) {
    arrivals += r[i].segmentation_ms >= 0;
    if (r[i].segmentation_ms >= 0) {
      have_masks = true;
      EXPECT_EQ(r[i].segmentation_ms, r[i].segmentation.ms);  // the backend's own timing
      // Past the first frame, which waits for its own, masks arrive after the frame they were computed on.
      EXPECT_GE(r[i].mask_age_frames, i == 0 ? 0 : 1) << "frame " << i;
    }
    if (have_masks) {
      EXPECT_GE(r[i].mask_age_frames, 0) << "frame " << i << ": masks must be carried to later frames";
      EXPECT_FALSE(r[i].segmentation.empty());
    } else {
      EXPECT_EQ(r[i].mask_age_frames, -1);
      EXPECT_TRUE(r[i].segmentation.empty());
    }
  }
  EXPECT_GE(arrivals, 1);
  // The first frame's masks (two persons in view) come with their instances.
  EXPECT_TRUE(have_masks);
}

TEST(DynamicFilterSchedule, TheFirstFrameWaitsForItsOwnMasksAndLaterOnesDoNot) {
  std::atomic<int> calls{0}, concurrent{0};
  DynamicFilterOptions o;
  o.segment_every = 1;
  DynamicFilter filter(frames().camera, o,
                       std::make_unique<SlowSegmenter>(std::chrono::milliseconds(150), &calls, &concurrent), true);
  const RgbdFrame first = frames().rendered[0].toRgbdFrame();
  FrameFeatures f = extractFeatures(first, cv::Mat(), frames().camera, FeatureOptions{});
  const size_t extracted = f.points.size();
  const DynamicFrameResult r0 = filter.process(first, &f, std::nullopt);
  EXPECT_EQ(r0.mask_age_frames, 0) << "the map starts from this frame: it must have its own masks";
  EXPECT_TRUE(r0.fresh_segmentation);
  ASSERT_FALSE(r0.segmentation.empty());
  EXPECT_LT(f.points.size(), extracted) << "the persons' keypoints are removed on the first frame already";
  // The next frame does not wait: it asks for its own masks and goes on with frame 0's
  // (age 0 would mean it had waited for them).
  const RgbdFrame second = frames().rendered[1].toRgbdFrame();
  FrameFeatures g = extractFeatures(second, cv::Mat(), frames().camera, FeatureOptions{});
  const DynamicFrameResult r1 = filter.process(second, &g, std::nullopt);
  EXPECT_EQ(r1.mask_age_frames, 1) << "frame 1 uses frame 0's masks";
  EXPECT_FALSE(r1.segmentation.empty());
}

TEST(DynamicFilterSchedule, DestroyingTheFilterWhileTheWorkerIsBusyWaitsForItAndReturns) {
  std::atomic<int> calls{0}, concurrent{0};
  {
    DynamicFilter filter(frames().camera, DynamicFilterOptions{},
                         std::make_unique<SlowSegmenter>(std::chrono::milliseconds(300), &calls, &concurrent), true);
    const RgbdFrame frame = frames().rendered[0].toRgbdFrame();
    FrameFeatures f = extractFeatures(frame, cv::Mat(), frames().camera, FeatureOptions{});
    filter.process(frame, &f, std::nullopt);
    // Let the worker pick the frame up, then destroy the filter while it is segmenting.
    for (int i = 0; i < 100 && calls.load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_EQ(calls.load(), 1);
  }
  EXPECT_EQ(calls.load(), 1);
}

TEST(DynamicFilterSchedule, ADisabledFilterNeitherSegmentsNorRemovesFeatures) {
  std::atomic<int> calls{0}, concurrent{0};
  DynamicFilterOptions o;
  o.enabled = false;
  DynamicFilter filter(frames().camera, o,
                       std::make_unique<SlowSegmenter>(std::chrono::milliseconds(0), &calls, &concurrent), false);
  for (const DynamicFrameResult& r : runFilter(&filter, std::chrono::milliseconds(0))) {
    EXPECT_TRUE(r.mask.empty());
    EXPECT_EQ(r.points_rejected, 0);
  }
  EXPECT_EQ(calls.load(), 0);
}

}  // namespace
}  // namespace plslam
