// Frame sources and the recorder: the replay grabber keeps camera rate and the recorded
// stamps, the recorder writes a folder that reads back bit for bit, and a build without
// RealSense support says so clearly.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "camera/camera_file.h"
#include "capture/frame_grabber.h"
#include "capture/replay_grabber.h"
#include "capture/tum_recorder.h"
#include "core/error.h"
#include "io/dataset.h"
#include "support/test_support.h"
#include "synthetic_cache.h"

using namespace plslam;

namespace {

bool sameImage(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  cv::Mat diff;
  cv::compare(a, b, diff, cv::CMP_NE);
  if (diff.channels() > 1) diff = diff.reshape(1);
  return cv::countNonZero(diff) == 0;
}

// NaN == NaN for depth maps.
bool sameDepth(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const float u = a.at<float>(y, x), v = b.at<float>(y, x);
      if (!(u == v || (std::isnan(u) && std::isnan(v)))) return false;
    }
  return true;
}

}  // namespace

TEST(ReplayGrabber, PlaysAtTheStampsRateAndKeepsTheStamps) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  TumDataset data = TumDataset::open(dir, camera);
  ReplayOptions o;
  o.max_frames = 15;
  ReplayGrabber grabber(dir, o);
  grabber.open();
  EXPECT_EQ(grabber.intrinsics().fx, camera.fx);
  RgbdFrame frame;
  std::vector<TimeNs> stamps;
  const auto start = std::chrono::steady_clock::now();
  while (grabber.grab(&frame)) {
    ASSERT_EQ(frame.bgr.type(), CV_8UC3);
    ASSERT_EQ(frame.depth_m.type(), CV_32FC1);
    stamps.push_back(frame.t_ns);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(stamps.size(), 15u);
  const std::vector<TimeNs> expected = data.stamps();
  for (size_t i = 0; i < stamps.size(); ++i) EXPECT_EQ(stamps[i], expected[i]);
  // Sleeping to the stamps: the replay cannot be faster than the recording (a lower bound only).
  EXPECT_GE(wall, nsToSeconds(stamps.back() - stamps.front()) - 1e-3);
  EXPECT_FALSE(grabber.grab(&frame)) << "the end of the replay stays the end";
}

TEST(ReplayGrabber, CloseEndsTheStream) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  ReplayGrabber grabber(dir);
  grabber.open();
  RgbdFrame frame;
  ASSERT_TRUE(grabber.grab(&frame));
  grabber.close();
  EXPECT_FALSE(grabber.grab(&frame));
}

TEST(TumRecorder, RecordingReadsBackBitForBit) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  const std::string out = test::scratchDir("recorder") + "/rec";
  DatasetOptions dopt;
  dopt.max_frames = 10;
  dopt.load_masks = false;
  TumDataset source = TumDataset::open(dir, camera, dopt);
  std::vector<RgbdFrame> frames;
  {
    TumRecorder recorder(out, camera);
    RgbdFrame f;
    while (source.next(&f)) {
      frames.push_back(f);
      recorder.add(f);
    }
    recorder.close();
    EXPECT_EQ(recorder.written(), 10);
  }
  const PinholeCamera recorded_camera = loadCameraFile(out + "/camera.xml");
  EXPECT_EQ(recorded_camera.fx, camera.fx);
  EXPECT_EQ(recorded_camera.depth_scale, camera.depth_scale);
  TumDataset back = TumDataset::open(out, recorded_camera);
  ASSERT_EQ(back.size(), frames.size());
  RgbdFrame g;
  for (const RgbdFrame& f : frames) {
    ASSERT_TRUE(back.next(&g));
    EXPECT_EQ(g.t_ns, f.t_ns);
    EXPECT_TRUE(sameImage(g.bgr, f.bgr)) << "colour of " << f.name;
    EXPECT_TRUE(sameDepth(g.depth_m, f.depth_m)) << "depth of " << f.name;
  }
}

TEST(TumRecorder, RefusesAFolderThatHoldsARecording) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  try {
    TumRecorder recorder(dir, camera);
    FAIL() << "recording over " << dir << " was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(dir), std::string::npos) << e.what();
  }
}

TEST(RealSense, UnavailableBuildSaysWhyAndHow) {
  if (realSenseAvailable()) GTEST_SKIP() << "this ViSP has librealsense2: nothing to check";
  const std::string message = realSenseUnavailableMessage();
  EXPECT_NE(message.find("librealsense2"), std::string::npos) << message;
  EXPECT_NE(message.find("-DUSE_REALSENSE2=ON"), std::string::npos) << message;
  try {
    makeRealSenseGrabber();
    FAIL() << "a RealSense grabber was made without RealSense support";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

// A frame that does not fit the recorder's camera (a grabber bug, a changed resolution) is
// refused with a DataError naming the sizes; the frames before it are kept and read back.
TEST(TumRecorder, RefusesAFrameOfAnotherSizeAndKeepsTheOthers) {
  const std::string dir = test::syntheticSequence(synth::SceneKind::kStatic, 120);
  const PinholeCamera camera = loadCameraFile(dir + "/camera.xml");
  const std::string out = test::scratchDir("recorder_size") + "/rec";
  DatasetOptions dopt;
  dopt.max_frames = 3;
  dopt.load_masks = false;
  TumDataset source = TumDataset::open(dir, camera, dopt);
  TumRecorder recorder(out, camera);
  RgbdFrame f;
  ASSERT_TRUE(source.next(&f));
  recorder.add(f);
  ASSERT_TRUE(source.next(&f));
  RgbdFrame half = f;
  cv::resize(f.bgr, half.bgr, cv::Size(), 0.5, 0.5);
  try {
    recorder.add(half);
    FAIL() << "a " << half.bgr.cols << "x" << half.bgr.rows << " frame was recorded for a " << camera.width << "x"
           << camera.height << " camera";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(half.bgr.cols) + "x" + std::to_string(half.bgr.rows)),
              std::string::npos)
        << e.what();
  }
  ASSERT_TRUE(source.next(&f));
  recorder.add(f);
  recorder.close();
  EXPECT_EQ(recorder.written(), 2);
  EXPECT_EQ(TumDataset::open(out, loadCameraFile(out + "/camera.xml")).size(), 2u);
}
