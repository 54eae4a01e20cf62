// ROS 1 messages and bags: conversions round-trip, and `plslam run` on a bag written with
// the rosbag API gives what it gives on the folder the bag was written from.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "camera/camera_file.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "ros1/bag_source.h"
#include "ros1/msg_convert.h"
#include "ros_fixture.h"
#include "support/test_support.h"
#include "synthetic_cache.h"

using namespace plslam;

TEST(RosConvert, ImagesAndCameraRoundTrip) {
  cv::Mat bgr(4, 5, CV_8UC3);
  cv::randu(bgr, 0, 255);
  for (const char* encoding : {"rgb8", "bgr8"}) {
    const cv::Mat back = ros1::colourToBgr(ros1::bgrToImage(bgr, encoding));
    EXPECT_EQ(cv::norm(back, bgr, cv::NORM_INF), 0) << encoding;
  }
  cv::Mat depth(4, 5, CV_32FC1, cv::Scalar(1.2346f));
  depth.at<float>(1, 2) = std::nanf("");
  const cv::Mat metres = ros1::depthToMetres(ros1::depthToImage(depth, false));
  EXPECT_FLOAT_EQ(metres.at<float>(0, 0), 1.2346f);
  EXPECT_TRUE(std::isnan(metres.at<float>(1, 2)));
  const cv::Mat mm = ros1::depthToMetres(ros1::depthToImage(depth, true));
  EXPECT_NEAR(mm.at<float>(0, 0), 1.235f, 1e-6);  // millimetres: rounded
  EXPECT_TRUE(std::isnan(mm.at<float>(1, 2)));

  PinholeCamera c;
  c.width = 640, c.height = 480, c.fx = 517.3, c.fy = 516.5, c.cx = 318.6, c.cy = 255.3;
  c.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  const PinholeCamera back = ros1::cameraFromInfo(ros1::infoFromCamera(c));
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.fx, c.fx);
  EXPECT_EQ(back.cy, c.cy);
  EXPECT_EQ(back.dist, c.dist);
  EXPECT_EQ(ros1::toNs(ros1::toRosTime(1305031102175304000LL)), 1305031102175304000LL);
}

TEST(RosConvert, UnsupportedEncodingsAreRefusedNamingThem) {
  sensor_msgs::Image msg = ros1::bgrToImage(cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)));
  msg.encoding = "yuv422";
  try {
    ros1::colourToBgr(msg);
    FAIL() << "yuv422 accepted";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("yuv422"), std::string::npos) << e.what();
  }
  msg.encoding = "rgb8";
  msg.data.resize(5);  // shorter than its pixels
  EXPECT_THROW(ros1::colourToBgr(msg), DataError);
}

namespace {

std::string runArgs(const std::string& dataset, const std::string& out) {
  return "run --dataset " + dataset + " --out " + out + " --sequential --quiet --no-dense";
}

}  // namespace

TEST(RosBag, SequentialRunGivesTheFolderTrajectory) {
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 60);
  const std::string scratch = test::scratchDir("rosbag");
  const std::string bag = scratch + "/static.bag";
  ASSERT_EQ(test::writeBagFromFolder(folder, bag, test::BagLayout::kTum), 60);

  const auto from_folder = test::runPlslam(runArgs(folder, scratch + "/folder") + " --calib " + folder + "/camera.xml");
  ASSERT_EQ(from_folder.status, 0) << from_folder.output;
  // The bag's camera_info, not a camera file: the intrinsics travel with the bag.
  const auto from_bag = test::runPlslam(runArgs(bag, scratch + "/bag") + " --groundtruth " + folder + "/groundtruth.txt");
  ASSERT_EQ(from_bag.status, 0) << from_bag.output;
  EXPECT_NE(from_bag.output.find("ATE RMSE"), std::string::npos) << from_bag.output;
  const std::string a = test::readFile(scratch + "/folder/trajectory.txt");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, test::readFile(scratch + "/bag/trajectory.txt"));
  const nlohmann::json stats = test::readJson(scratch + "/bag/stats.json");
  EXPECT_NE(stats.at("dataset").get<std::string>().find(bag), std::string::npos) << stats;
}

TEST(RosBag, RealSenseLayoutInMillimetresTracksAsWell) {
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 60);
  const std::string scratch = test::scratchDir("rosbag_rs");
  const std::string bag = scratch + "/realsense.bag";
  ASSERT_EQ(test::writeBagFromFolder(folder, bag, test::BagLayout::kRealSense), 60);
  auto source = ros1::BagSource::open(bag);
  EXPECT_EQ(source->topics().depth, "/camera/aligned_depth_to_color/image_raw");
  EXPECT_EQ(source->size(), 60u);
  const auto r = test::runPlslam(runArgs(bag, scratch + "/out"));
  ASSERT_EQ(r.status, 0) << r.output;
  const EvalResult ev = evaluate(readTumTrajectory(folder + "/groundtruth.txt"), readTumTrajectory(scratch + "/out/trajectory.txt"));
  EXPECT_EQ(ev.ate.stats.count, 60);
  EXPECT_LT(ev.ate.stats.rmse, 0.02);  // depth quantised to millimetres: not identical, as accurate
}

TEST(RosBag, ABagWithoutKnownTopicsIsRefusedListingItsTopics) {
  const std::string scratch = test::scratchDir("rosbag_bad");
  const std::string bag = scratch + "/other.bag";
  {
    rosbag::Bag b(bag, rosbag::bagmode::Write);
    b.write("/scan_like", ros::Time(1, 0), ros1::infoFromCamera(PinholeCamera()));
  }
  const auto r = test::runPlslam(runArgs(bag, scratch + "/out"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("/scan_like"), std::string::npos) << r.output;
}

TEST(RosBag, PairsByStampAndCountsFramesItCannotConvert) {
  const std::string bag_path = test::scratchDir("rosbag_skip") + "/small.bag";
  PinholeCamera camera;
  camera.width = 8, camera.height = 6, camera.fx = camera.fy = 10, camera.cx = 4, camera.cy = 3;
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    bag.write("/camera/color/camera_info", ros::Time(100, 0), ros1::infoFromCamera(camera));
    for (int i = 0; i < 3; ++i) {
      sensor_msgs::Image colour = ros1::bgrToImage(cv::Mat(6, 8, CV_8UC3, cv::Scalar(i, i, i)));
      sensor_msgs::Image depth = ros1::depthToImage(cv::Mat(6, 8, CV_32FC1, cv::Scalar(1.0f)), true);
      colour.header.stamp = ros::Time(100, i * 33000000);
      depth.header.stamp = ros::Time(100, i * 33000000 + 5000000);  // 5 ms later: still a pair
      if (i == 1) colour.encoding = "yuv422";
      bag.write("/camera/color/image_raw", colour.header.stamp, colour);
      bag.write("/camera/aligned_depth_to_color/image_raw", depth.header.stamp, depth);
    }
  }
  auto source = ros1::BagSource::open(bag_path);
  EXPECT_EQ(source->size(), 3u);
  EXPECT_EQ(source->camera().width, 8);
  std::vector<TimeNs> stamps;
  RgbdFrame frame;
  while (source->next(&frame)) stamps.push_back(frame.t_ns);
  EXPECT_EQ(stamps, (std::vector<TimeNs>{100000000000LL, 100066000000LL}));
  EXPECT_EQ(source->skippedTotal(), 1);
  EXPECT_NE(source->skippedText().find("yuv422"), std::string::npos) << source->skippedText();
}

// `plslam record --bag` (here of the replay grabber, as the record tests use it) writes TUM's
// bag layout, which reads back as the frames recorded: same stamps, colour, depth and camera.
TEST(RosBag, RecordedBagReadsBackWithTheSameFrames) {
  constexpr int kFrames = 15;
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, kFrames);
  const std::string bag = test::scratchDir("rosbag_record") + "/recorded.bag";
  const auto r = test::runPlslam("record --fake " + folder + " --fake-speed 0 --bag " + bag);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("recorded " + std::to_string(kFrames) + " frames"), std::string::npos) << r.output;
  auto source = ros1::BagSource::open(bag);
  EXPECT_EQ(source->topics().colour, "/camera/rgb/image_color");
  EXPECT_EQ(source->topics().depth, "/camera/depth/image");
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  const PinholeCamera& read = source->camera();
  EXPECT_EQ(read.width, camera.width);
  EXPECT_EQ(read.height, camera.height);
  EXPECT_DOUBLE_EQ(read.fx, camera.fx);
  EXPECT_DOUBLE_EQ(read.fy, camera.fy);
  EXPECT_DOUBLE_EQ(read.cx, camera.cx);
  EXPECT_DOUBLE_EQ(read.cy, camera.cy);
  ASSERT_EQ(source->size(), static_cast<size_t>(kFrames));
  TumDataset dataset = TumDataset::open(folder, camera);
  RgbdFrame from_bag, from_folder;
  int n = 0;
  while (source->next(&from_bag)) {
    ASSERT_TRUE(dataset.next(&from_folder));
    EXPECT_EQ(from_bag.t_ns, from_folder.t_ns) << n;
    EXPECT_EQ(cv::norm(from_bag.bgr, from_folder.bgr, cv::NORM_INF), 0) << n;
    EXPECT_EQ(cv::norm(from_bag.depth_m, from_folder.depth_m, cv::NORM_INF), 0) << n;
    ++n;
  }
  EXPECT_EQ(n, kFrames);
  EXPECT_EQ(source->skippedTotal(), 0);
  // One of --out and --bag.
  EXPECT_NE(test::runPlslam("record --fake " + folder + " --bag " + bag + " --out " + bag + ".dir").status, 0);
}
