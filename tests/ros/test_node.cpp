// The plslam_ros node end to end, on a private rosmaster (127.0.0.1, free port): the
// synthetic static sequence published as RealSense topics at 30 Hz, restamped with the
// publication time (so the node's latency is image stamp -> pose), and checks of the TF
// tree, the poses (ATE against the scene's ground truth, next to `plslam run` threaded on
// the same frames), the sparse map, the dense cloud and the grid (maps while running) in
// the map frame, the save service and the outputs
// written on SIGINT; the goal servo's and the tag servo's cmd_vel. Prints the latency and drop figures that docs/RESULTS.md quotes;
// PLSLAM_ROS_NODE_PARAMS (e.g. "_queue:=1") adds node parameters for such measurements.
#include <gtest/gtest.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <signal.h>
#include <std_msgs/Empty.h>
#include <std_msgs/Int32.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <tuple>
#include <vector>

#include "camera/camera_file.h"
#include "core/map_frame.h"
#include "eval/trajectory_eval.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "ros1/msg_convert.h"
#include "plslam_ros/ros_messages.h"
#include "servo_sim/tag_room.h"
#include "ros_fixture.h"
#include "support/test_support.h"
#include "synthetic_cache.h"

using namespace plslam;
namespace fs = std::filesystem;

namespace {

// The plslam_ros node in a child process, stopped when it goes out of scope: a failed ASSERT
// returns from the test, and a node left running would hold ctest's output pipe open and hang
// the whole suite. It also dies with the test process (PR_SET_PDEATHSIG).
class NodeProcess {
 public:
  NodeProcess(const std::string& out, const std::vector<std::string>& params) {
    pid_ = fork();
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      const std::string exe = test::binaryDir() + "/plslam_ros";
      std::vector<std::string> args = {exe, "__name:=plslam", "_out:=" + out};
      args.insert(args.end(), params.begin(), params.end());
      if (const char* extra = std::getenv("PLSLAM_ROS_NODE_PARAMS")) {
        std::istringstream words(extra);
        for (std::string w; words >> w;) args.push_back(w);
      }
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(exe.c_str(), argv.data());
      _exit(127);
    }
  }
  ~NodeProcess() {
    if (pid_ > 0) stop();
  }
  NodeProcess(const NodeProcess&) = delete;
  NodeProcess& operator=(const NodeProcess&) = delete;

  bool started() const { return pid_ > 0; }

  /// SIGINT, as a user's Ctrl-C; the node writes its outputs and exits. Its exit status, or
  /// -1 when it died by a signal or had to be killed after kStopTimeoutS.
  int stop() {
    if (pid_ <= 0) return -1;
    const std::optional<int> status = test::stopChild(pid_, SIGINT, kStopTimeoutS);
    pid_ = -1;
    if (!status) {
      ADD_FAILURE() << "the node did not stop within " << kStopTimeoutS << " s of SIGINT: killed";
      return -1;
    }
    return WIFEXITED(*status) ? WEXITSTATUS(*status) : -1;
  }

 private:
  static constexpr int kStopTimeoutS = 60;
  pid_t pid_ = -1;
};

// The node's own counters of stats.json (ros_*), for the figures line.
std::string rosCounts(const nlohmann::json& stats) {
  std::string out;
  if (stats.is_object())
    for (const auto& [key, value] : stats.items())
      if (key.rfind("ros_", 0) == 0) out += key + " " + value.dump() + " ";
  return out;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

// How CameraPlayer::play sends a folder.
struct Play {
  std::string camera_file;   ///< empty: <folder>/camera.xml
  bool restamp = true;       ///< stamp each frame when it is sent (else: the folder's stamps)
  bool millimetres = true;   ///< depth as 16UC1 millimetres (else 32FC1 metres)
  int skip = 0;              ///< frames of the folder not sent before the first one sent
};

// This test process as a ROS node: the camera's publishers, and what it hears back.
class CameraPlayer {
 public:
  CameraPlayer() {
    int argc = 1;
    char name[] = "plslam_test";
    char* argv[] = {name, nullptr};
    if (!ros::isInitialized())
      ros::init(argc, argv, "plslam_test", ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
    nh_ = std::make_unique<ros::NodeHandle>();
    spinner_ = std::make_unique<ros::AsyncSpinner>(2);
    spinner_->start();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer);
    pose_sub_ = nh_->subscribe<geometry_msgs::PoseStamped>("/plslam/camera_pose", 400, [this](const auto& msg) {
      std::lock_guard<std::mutex> lock(mutex);
      latency_ms[ros1::toNs(msg->header.stamp)] = (ros::Time::now() - msg->header.stamp).toSec() * 1000.0;
      camera_poses[ros1::toNs(msg->header.stamp)] = msg->pose;
    });
    base_sub_ = nh_->subscribe<geometry_msgs::PoseStamped>("/plslam/base_pose", 400, [this](const auto& msg) {
      std::lock_guard<std::mutex> lock(mutex);
      last_base = *msg;
    });
    cloud_sub_ = nh_->subscribe<sensor_msgs::PointCloud2>("/plslam/sparse_points", 1, [this](const auto& msg) {
      std::lock_guard<std::mutex> lock(mutex);
      cloud_frame = msg->header.frame_id;
      cloud_points = static_cast<size_t>(msg->width) * msg->height;
    });
    dense_sub_ = nh_->subscribe<sensor_msgs::PointCloud2>("/plslam/dense_cloud", 1, [this](const auto& msg) {
      std::lock_guard<std::mutex> lock(mutex);
      ++dense_messages;
      dense_frame = msg->header.frame_id;
      dense_points = static_cast<size_t>(msg->width) * msg->height;
      dense_label_field = false;
      for (const sensor_msgs::PointField& f : msg->fields)
        dense_label_field |= f.name == "label" && f.datatype == sensor_msgs::PointField::UINT32;
    });
    grid_sub_ = nh_->subscribe<nav_msgs::OccupancyGrid>("/plslam/grid", 1, [this](const auto& msg) {
      std::lock_guard<std::mutex> lock(mutex);
      ++grid_messages;
      grid_frame = msg->header.frame_id;
      grid_cells = msg->data.size();
      grid_occupied = static_cast<size_t>(std::count(msg->data.begin(), msg->data.end(), 100));
    });
    colour_pub_ = nh_->advertise<sensor_msgs::Image>("/camera/color/image_raw", 5);
    depth_pub_ = nh_->advertise<sensor_msgs::Image>("/camera/aligned_depth_to_color/image_raw", 5);
    info_pub_ = nh_->advertise<sensor_msgs::CameraInfo>("/camera/color/camera_info", 1, true);
  }
  ~CameraPlayer() { spinner_->stop(); }

  /// Waits for the node's subscriptions, then plays `folder` at 30 Hz. With restamp, returns
  /// the ground truth (one pose per frame, as plslam synth writes it) under the new stamps.
  Trajectory play(const std::string& folder, int frames, const Play& how = Play()) {
    const PinholeCamera camera = loadCameraFile(how.camera_file.empty() ? folder + "/camera.xml" : how.camera_file);
    TumDataset dataset = TumDataset::open(folder, camera);
    sensor_msgs::CameraInfo info = ros1::infoFromCamera(camera);
    info.header.frame_id = "camera_color_optical_frame";
    info_pub_.publish(info);
    // The node drops its camera_info subscription once it has the intrinsics: only the first
    // play waits for it (later ones would wait out the 20 s for nothing).
    for (int i = 0; i < 200 && (colour_pub_.getNumSubscribers() == 0 || depth_pub_.getNumSubscribers() == 0 ||
                                (first_play_ && info_pub_.getNumSubscribers() == 0)); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    first_play_ = false;
    EXPECT_GT(colour_pub_.getNumSubscribers(), 0u) << "the node did not subscribe";
    std::this_thread::sleep_for(std::chrono::seconds(1));  // the latched camera_info reaches it first
    Trajectory groundtruth;
    RgbdFrame frame;
    for (int i = 0; i < how.skip && dataset.next(&frame); ++i) {
    }
    ros::WallRate rate(30.0);
    for (int i = how.skip; i < how.skip + frames && dataset.next(&frame); ++i) {
      sensor_msgs::Image colour = ros1::bgrToImage(frame.bgr, "rgb8");
      sensor_msgs::Image depth = ros1::depthToImage(frame.depth_m, how.millimetres);
      colour.header.frame_id = depth.header.frame_id = "camera_color_optical_frame";
      colour.header.stamp = depth.header.stamp = how.restamp ? ros::Time::now() : ros1::toRosTime(frame.t_ns);
      if (how.restamp) groundtruth.push_back({ros1::toNs(colour.header.stamp), dataset.groundtruth()[i].T_w_c});
      colour_pub_.publish(colour);
      depth_pub_.publish(depth);
      rate.sleep();
    }
    std::this_thread::sleep_for(std::chrono::seconds(3));  // the last frames' poses, a sparse map refresh
    return groundtruth;
  }

  /// Waits for the node's subscriptions (and, the first time, its camera_info), then sends
  /// `frames` views of `room` from T_room_c at 30 Hz, stamped when sent.
  void playViews(const TagRoom& room, const SE3& T_room_c, int frames) {
    sensor_msgs::CameraInfo info = ros1::infoFromCamera(room.camera());
    info.header.frame_id = "camera_color_optical_frame";
    info_pub_.publish(info);
    for (int i = 0; i < 200 && (colour_pub_.getNumSubscribers() == 0 || depth_pub_.getNumSubscribers() == 0 ||
                                (first_play_ && info_pub_.getNumSubscribers() == 0)); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_GT(colour_pub_.getNumSubscribers(), 0u) << "the node did not subscribe";
    if (first_play_) std::this_thread::sleep_for(std::chrono::seconds(1));  // the latched camera_info reaches it first
    first_play_ = false;
    ros::WallRate rate(30.0);
    for (int i = 0; i < frames; ++i) {
      const synth::RenderedFrame view = room.render(T_room_c, 0, static_cast<uint64_t>(++views_));
      sensor_msgs::Image colour = ros1::bgrToImage(view.bgr, "rgb8");
      sensor_msgs::Image depth = ros1::depthToImage(view.depth_m, true);
      colour.header.frame_id = depth.header.frame_id = "camera_color_optical_frame";
      colour.header.stamp = depth.header.stamp = ros::Time::now();
      colour_pub_.publish(colour);
      depth_pub_.publish(depth);
      rate.sleep();
    }
  }

  tf2_ros::Buffer tf_buffer;
  std::mutex mutex;
  std::map<TimeNs, double> latency_ms;  // pose stamp -> receive time - stamp
  std::map<TimeNs, geometry_msgs::Pose> camera_poses;  // pose stamp -> camera pose
  geometry_msgs::PoseStamped last_base;
  std::string cloud_frame;
  size_t cloud_points = 0;
  int dense_messages = 0, grid_messages = 0;  // the maps while running, as published
  std::string dense_frame, grid_frame;
  size_t dense_points = 0, grid_cells = 0, grid_occupied = 0;
  bool dense_label_field = false;

 private:
  std::unique_ptr<ros::NodeHandle> nh_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Subscriber pose_sub_, base_sub_, cloud_sub_, dense_sub_, grid_sub_;
  ros::Publisher colour_pub_, depth_pub_, info_pub_;
  bool first_play_ = true;
  int views_ = 0;  // playViews' frames sent: each its own sensor noise
};

}  // namespace

TEST(RosNode, PublishesPosesTfAndMapsAndWritesOutputs) {
  constexpr int kFrames = 300;
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, kFrames);
  const std::string scratch = test::scratchDir("rosnode");
  const std::string out = scratch + "/node";
  NodeProcess node(out, {"_sparse_period:=0.5"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  const Trajectory groundtruth = player.play(folder, kFrames);

  // TF: map -> base_footprint (no odometry frame given).
  EXPECT_TRUE(player.tf_buffer.canTransform("map", "base_footprint", ros::Time(0), ros::Duration(1.0)));
  {
    std::lock_guard<std::mutex> lock(player.mutex);
    EXPECT_EQ(player.cloud_frame, "map");
    EXPECT_GT(player.cloud_points, 100u);
    // How many frames the node keeps up with depends on the machine's load; it drops the
    // oldest rather than fall behind, so only a fair share is required here.
    EXPECT_GT(player.latency_ms.size(), kFrames / 5u);
    // The maps while running (dense.live_every_s 5 s by default), before the node stops.
    EXPECT_GE(player.dense_messages, 1);
    EXPECT_EQ(player.dense_frame, "map");
    EXPECT_GT(player.dense_points, 1000u);
    EXPECT_TRUE(player.dense_label_field);
    EXPECT_GE(player.grid_messages, 1);
    EXPECT_EQ(player.grid_frame, "map");
    EXPECT_GT(player.grid_cells, 0u);
    EXPECT_GT(player.grid_occupied, 0u);
    std::printf("[figures] node: %d dense cloud and %d grid messages while running; last cloud %zu points, grid %zu cells "
                "(%zu occupied)\n", player.dense_messages, player.grid_messages, player.dense_points, player.grid_cells,
                player.grid_occupied);
  }
  // The save service writes the outputs while the node runs; `plslam export` reads its map.
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call("/plslam/save_map", save));
  EXPECT_TRUE(save.response.success) << save.response.message;
  const auto exported = test::runPlslam("export --map " + out + "/map.plmap --out " + scratch + "/export --grid");
  EXPECT_EQ(exported.status, 0) << exported.output;
  EXPECT_TRUE(fs::exists(scratch + "/export/grid.pgm"));

  EXPECT_EQ(node.stop(), 0);
  for (const char* f : {"trajectory.txt", "stats.json", "map.plmap", "dense_cloud.pcd", "grid.pgm"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const EvalResult node_ev = evaluate(groundtruth, readTumTrajectory(out + "/trajectory.txt"));
  // plslam run, threaded, on the same frames.
  const auto run = test::runPlslam("run --dataset " + folder + " --calib " + folder + "/camera.xml --out " + scratch +
                                   "/run --quiet --no-dense");
  ASSERT_EQ(run.status, 0) << run.output;
  const EvalResult run_ev = evaluate(readTumTrajectory(folder + "/groundtruth.txt"),
                                     readTumTrajectory(scratch + "/run/trajectory.txt"));
  std::vector<double> latency;
  for (const auto& [t, ms] : player.latency_ms) latency.push_back(ms);
  const nlohmann::json stats = test::readJson(out + "/stats.json");
  EXPECT_TRUE(stats.contains("ros_received")) << stats;
  std::printf("[figures] node: %zu poses of %d frames published; latency image stamp -> pose received: median %.1f ms, "
              "p95 %.1f ms; ATE node %.4f m (%d poses), plslam run threaded %.4f m (%d poses)\n[figures] node stats: %s\n",
              latency.size(), kFrames, percentile(latency, 0.5), percentile(latency, 0.95), node_ev.ate.stats.rmse,
              node_ev.ate.stats.count, run_ev.ate.stats.rmse, run_ev.ate.stats.count, rosCounts(stats).c_str());
  EXPECT_LT(node_ev.ate.stats.rmse, std::max(0.02, 2 * run_ev.ate.stats.rmse));
}

TEST(RosNode, WithAnOdometryFramePublishesMapToOdom) {
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 60);
  const std::string scratch = test::scratchDir("rosnode_odom");
  NodeProcess node(scratch + "/node", {"_odom_frame:=odom", "_no_dense:=true"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  // The wheel odometry, here a fixed odom -> base_footprint.
  tf2_ros::StaticTransformBroadcaster odometry;
  geometry_msgs::TransformStamped odom_base;
  odom_base.header.frame_id = "odom";
  odom_base.child_frame_id = "base_footprint";
  odom_base.transform.translation.x = 0.5;
  odom_base.transform.rotation.w = 1;
  odometry.sendTransform(odom_base);
  player.play(folder, 60);

  ASSERT_TRUE(player.tf_buffer.canTransform("map", "odom", ros::Time(0), ros::Duration(1.0)));
  const auto map_base = player.tf_buffer.lookupTransform("map", "base_footprint", ros::Time(0));
  geometry_msgs::PoseStamped base;
  {
    std::lock_guard<std::mutex> lock(player.mutex);
    base = player.last_base;
  }
  // map -> odom -> base_footprint is the node's base pose.
  EXPECT_NEAR(map_base.transform.translation.x, base.pose.position.x, 1e-6);
  EXPECT_NEAR(map_base.transform.translation.y, base.pose.position.y, 1e-6);
  EXPECT_NEAR(map_base.transform.translation.z, base.pose.position.z, 1e-6);
  EXPECT_EQ(node.stop(), 0);
}

// One map frame for TF and the files: with a camera-to-base transform, the base pose the
// node publishes (map -> base_footprint) at the last frame is the one trajectory_base.txt
// holds for it in map_frame.yaml's frame (up to the refinement of poses after tracking).
// The mounting puts the base 0.20 m below the camera, which in the scene stands about 1.5 m
// above the floor: in the provisional frame (the base at the first frame) the base would be
// at z = 0, in the files' frame it is 1.3 m above the floor.
TEST(RosNode, TfMapIsTheMapFrameOfTheFiles) {
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 90);
  const std::string scratch = test::scratchDir("rosnode_frame");
  std::ofstream(scratch + "/base.yaml") << "format: plslam_camera_to_base 1\nparent_frame: base\nchild_frame: camera\n"
                                           "translation: [0.10, 0, 0.20]\nrotation: [-0.5, 0.5, -0.5, 0.5]\n";
  NodeProcess node(scratch + "/node", {"_camera_to_base:=" + scratch + "/base.yaml", "_no_dense:=true"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  player.play(folder, 90);
  ASSERT_TRUE(player.tf_buffer.canTransform("map", "base_footprint", ros::Time(0), ros::Duration(1.0)));
  geometry_msgs::PoseStamped last;
  {
    std::lock_guard<std::mutex> lock(player.mutex);
    last = player.last_base;
  }
  const auto tf = player.tf_buffer.lookupTransform("map", "base_footprint", last.header.stamp);
  EXPECT_NEAR(tf.transform.translation.z, last.pose.position.z, 1e-6) << "TF and the base pose topic agree";
  EXPECT_EQ(node.stop(), 0);

  const MapFrame frame = parseMapFrameYaml(test::readFile(scratch + "/node/map_frame.yaml"), "map_frame.yaml");
  EXPECT_EQ(frame.origin, "base");
  const Trajectory base = readTumTrajectory(scratch + "/node/trajectory_base.txt");
  const TimeNs stamp = ros1::toNs(last.header.stamp);
  const auto it = std::find_if(base.begin(), base.end(), [&](const StampedPose& p) { return std::llabs(p.t_ns - stamp) < 1000; });
  ASSERT_NE(it, base.end()) << "the last published pose's stamp is in trajectory_base.txt";
  const Eigen::Vector3d published(last.pose.position.x, last.pose.position.y, last.pose.position.z);
  const Eigen::Quaterniond q(last.pose.orientation.w, last.pose.orientation.x, last.pose.orientation.y,
                             last.pose.orientation.z);
  const SE3 published_pose(q, published);
  std::printf("[figures] node TF base pose against trajectory_base.txt: %.4f m, %.4f deg; base %.3f m above the floor\n",
              (published - it->T_w_c.translation()).norm(), (published_pose.inverse() * it->T_w_c).angle() * 180 / M_PI,
              published.z());
  EXPECT_LT((published - it->T_w_c.translation()).norm(), 0.02);
  EXPECT_LT((published_pose.inverse() * it->T_w_c).angle() * 180 / M_PI, 1.0);
}

TEST(RosNode, RealSequenceAteNextToPlslamRun) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr1_xyz_0-199");
  const std::string folder = test::sharedDir() + "/data/tum/fr1_xyz_0-199";
  const std::string calib = test::sourceDir() + "/calib/tum_freiburg1.xml";
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string scratch = test::scratchDir("rosnode_fr1");
  NodeProcess node(scratch + "/node", {"_no_dense:=true"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  Play how;
  how.camera_file = calib;  // sent as camera_info, distortion included
  how.restamp = false;      // the recorded stamps, to compare with the ground truth
  how.millimetres = false;  // 32FC1 metres, as TUM's own bags
  player.play(folder, 200, how);
  EXPECT_EQ(node.stop(), 0);
  const Trajectory gt = readTumTrajectory(folder + "/groundtruth.txt");
  const EvalResult node_ev = evaluate(gt, readTumTrajectory(scratch + "/node/trajectory.txt"));
  const auto run = test::runPlslam("run --dataset " + folder + " --calib " + calib + " --out " + scratch +
                                   "/run --quiet --no-dense");
  ASSERT_EQ(run.status, 0) << run.output;
  const EvalResult run_ev = evaluate(gt, readTumTrajectory(scratch + "/run/trajectory.txt"));
  const nlohmann::json stats = test::readJson(scratch + "/node/stats.json");
  std::printf("[figures] fr1_xyz_0-199 at 30 Hz: ATE node %.4f m (%d poses), plslam run threaded %.4f m (%d poses)\n"
              "[figures] node stats: %s\n",
              node_ev.ate.stats.rmse, node_ev.ate.stats.count, run_ev.ate.stats.rmse, run_ev.ate.stats.count,
              rosCounts(stats).c_str());
  EXPECT_LT(node_ev.ate.stats.rmse, std::max(0.03, 2 * run_ev.ate.stats.rmse));
}

// The node takes the segmenter from its ~config file as plslam run does, and its
// ~segmenter parameter overrides the key (session/run_config.h, the one mapping).
TEST(RosNode, SegmenterComesFromTheConfigAndTheParameterOverridesIt) {
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 20);
  const std::string scratch = test::scratchDir("rosnode_segmenter");
  const std::string cfg = scratch + "/segmenter.yaml";
  // A model that cannot be used, allowed: the node goes on geometry-only but keeps the choice.
  std::ofstream(cfg) << "segmenter:\n  backend: yolo\n  model: /nonexistent/seg.onnx\n  allow_missing_model: true\n";
  for (const auto& [name, extra, expected] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"by_key", "", "yolo"},
                                                                        {"by_param", "_segmenter:=none", "none"}}) {
    const std::string out = scratch + "/" + name;
    std::vector<std::string> params = {"_config:=" + cfg, "_no_dense:=true"};
    if (!extra.empty()) params.push_back(extra);
    NodeProcess node(out, params);
    ASSERT_TRUE(node.started());
    {
      CameraPlayer player;
      player.play(folder, 20);
    }
    EXPECT_EQ(node.stop(), 0) << name;
    const std::string config = test::readFile(out + "/config.yaml");
    EXPECT_NE(config.find("backend: \"" + expected + "\""), std::string::npos) << name << "\n" << config;
    EXPECT_EQ(test::readJson(out + "/stats.json").at("dynamic").at("segmenter"), expected) << name;
  }
}

// ~reset drops the map: the path restarts, the latched dense cloud is emptied, and the
// outputs written at shutdown hold only the new map's poses (its world is the first camera
// after the reset).
TEST(RosNode, ResetServiceStartsANewMapAndPath) {
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 60);
  const std::string scratch = test::scratchDir("rosnode_reset");
  NodeProcess node(scratch + "/node", {});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  std::mutex path_mutex;
  nav_msgs::Path last_path;
  ros::NodeHandle nh;
  const ros::Subscriber path_sub = nh.subscribe<nav_msgs::Path>("/plslam/path", 10, [&](const auto& msg) {
    std::lock_guard<std::mutex> lock(path_mutex);
    last_path = *msg;
  });
  player.play(folder, 60);
  size_t path_before = 0;
  {
    std::lock_guard<std::mutex> lock(path_mutex);
    path_before = last_path.poses.size();
  }
  ASSERT_GT(path_before, 10u) << "the first map was tracked";
  int dense_before = 0;
  {
    std::lock_guard<std::mutex> lock(player.mutex);
    dense_before = player.dense_messages;
  }
  const ros::Time reset_at = ros::Time::now();
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("/plslam/reset", reset));
  EXPECT_TRUE(reset.response.success) << reset.response.message;
  // The latched dense cloud of the dropped map is replaced by an empty one.
  for (int i = 0; i < 100; ++i) {
    {
      std::lock_guard<std::mutex> lock(player.mutex);
      if (player.dense_messages > dense_before) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  {
    std::lock_guard<std::mutex> lock(player.mutex);
    ASSERT_GT(player.dense_messages, dense_before) << "a dense cloud message after the reset";
    EXPECT_EQ(player.dense_points, 0u);
  }
  player.play(folder, 30);  // the sequence from its start again: a place the new map has not seen either
  // On a loaded machine the node is still working through queued images when the player is
  // done: wait for the new map's path to stop growing (at most 10 s).
  nav_msgs::Path after;
  for (int quiet = 0, i = 0; quiet < 10 && i < 200; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::lock_guard<std::mutex> lock(path_mutex);
    const bool new_map = !last_path.poses.empty() && last_path.poses.front().header.stamp > reset_at;
    quiet = new_map && last_path.poses.size() == after.poses.size() ? quiet + 1 : 0;
    after = last_path;
  }
  EXPECT_EQ(node.stop(), 0);

  ASSERT_FALSE(after.poses.empty());
  EXPECT_LE(after.poses.size(), 30u) << "the path restarted at the reset";
  for (const geometry_msgs::PoseStamped& p : after.poses) EXPECT_GT(p.header.stamp, reset_at);
  const Trajectory written = readTumTrajectory(scratch + "/node/trajectory.txt");
  ASSERT_FALSE(written.empty());
  EXPECT_LE(written.size(), 30u);
  for (const StampedPose& p : written) EXPECT_GT(p.t_ns, ros1::toNs(reset_at));
  EXPECT_LT(written.front().T_w_c.translation().norm(), 1e-6) << "the new map's world is its first camera";
}

// ~localize true keeps the map as it is while the frames are still tracked in it (the
// sparse map the node publishes keeps its size, poses keep coming); false maps again.
TEST(RosNode, LocalizeServiceKeepsTheMapWhileTracking) {
  constexpr int kPart = 60;
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 3 * kPart);
  const std::string scratch = test::scratchDir("rosnode_localize");
  NodeProcess node(scratch + "/node", {"_no_dense:=true", "_sparse_period:=0.5"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  auto seen = [&] {
    std::lock_guard<std::mutex> lock(player.mutex);
    return std::make_pair(player.cloud_points, player.latency_ms.size());
  };
  player.play(folder, kPart);  // ends 3 s after the last frame: mapped, the sparse map republished
  const auto [mapped_points, poses_mapping] = seen();
  ASSERT_GT(mapped_points, 100u);
  std_srvs::SetBool localize;
  localize.request.data = true;
  ASSERT_TRUE(ros::service::call("/plslam/localize", localize));
  EXPECT_TRUE(localize.response.success) << localize.response.message;
  Play next;
  next.skip = kPart;
  player.play(folder, kPart, next);
  const auto [localised_points, poses_localising] = seen();
  EXPECT_EQ(localised_points, mapped_points) << "no landmark added or removed while localising";
  EXPECT_GT(poses_localising - poses_mapping, static_cast<size_t>(kPart / 5)) << "frames still tracked";
  localize.request.data = false;
  ASSERT_TRUE(ros::service::call("/plslam/localize", localize));
  EXPECT_TRUE(localize.response.success) << localize.response.message;
  next.skip = 2 * kPart;
  player.play(folder, kPart, next);
  EXPECT_NE(seen().first, mapped_points) << "mapping again";
  EXPECT_EQ(node.stop(), 0);
}

// Without a camera_to_base file, the mounting comes from TF (base_footprint -> the colour
// image's frame_id, here a static transform as robot_state_publisher would send it): the
// base pose the node publishes is the camera pose moved by it, and the map frame's origin is
// below the base.
TEST(RosNode, CameraToBaseFromTfPlacesTheBase) {
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, 60);
  const std::string scratch = test::scratchDir("rosnode_tf_base");
  CameraPlayer player;
  tf2_ros::StaticTransformBroadcaster robot;
  geometry_msgs::TransformStamped mounting;
  mounting.header.frame_id = "base_footprint";
  mounting.child_frame_id = "camera_color_optical_frame";  // the frame_id CameraPlayer stamps the images with
  mounting.transform.translation.x = 0.10;
  mounting.transform.translation.z = 0.20;
  mounting.transform.rotation.x = -0.5;
  mounting.transform.rotation.y = 0.5;
  mounting.transform.rotation.z = -0.5;
  mounting.transform.rotation.w = 0.5;
  robot.sendTransform(mounting);
  const SE3 T_base_cam(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(0.10, 0, 0.20));
  NodeProcess node(scratch + "/node", {"_no_dense:=true", "_tf_wait:=5.0"});
  ASSERT_TRUE(node.started());
  player.play(folder, 60);
  geometry_msgs::PoseStamped base;
  geometry_msgs::Pose camera;
  {
    std::lock_guard<std::mutex> lock(player.mutex);
    base = player.last_base;
    ASSERT_EQ(player.camera_poses.count(ros1::toNs(base.header.stamp)), 1u) << "a camera pose at the last base pose's stamp";
    camera = player.camera_poses[ros1::toNs(base.header.stamp)];
  }
  EXPECT_EQ(node.stop(), 0);
  // T_map_base = T_map_cam * T_base_cam^-1: the camera in the base frame is the TF mounting.
  const SE3 cam_in_base = ros1::fromPose(base.pose).inverse() * ros1::fromPose(camera);
  std::printf("[figures] node camera-to-base from TF: published base-to-camera off the TF mounting by %.2e m, %.2e deg\n",
              (cam_in_base.translation() - T_base_cam.translation()).norm(),
              (cam_in_base.inverse() * T_base_cam).angle() * 180 / M_PI);
  EXPECT_LT((cam_in_base.translation() - T_base_cam.translation()).norm(), 1e-5);
  EXPECT_LT((cam_in_base.inverse() * T_base_cam).angle(), 1e-5);
  const MapFrame frame = parseMapFrameYaml(test::readFile(scratch + "/node/map_frame.yaml"), "map_frame.yaml");
  EXPECT_EQ(frame.origin, "base") << "the outputs use the TF mounting too";
}

namespace {

// What the node sends on /cmd_vel, and the goal and cancel topics.
class GoalClient {
 public:
  GoalClient() {
    ros::NodeHandle nh;
    cmd_sub_ = nh.subscribe<geometry_msgs::Twist>("/cmd_vel", 400, [this](const auto& msg) {
      std::lock_guard<std::mutex> lock(mutex_);
      commands_.push_back(*msg);
    });
    goal_pub_ = nh.advertise<geometry_msgs::PoseStamped>("/plslam/goal", 1);
    cancel_pub_ = nh.advertise<std_msgs::Empty>("/plslam/cancel", 1);
  }

  /// Sends a goal `distance` metres from the base pose `base`, `bearing` radians off its
  /// heading (positive: left), in the map frame or, with `in_turned`, in the frame "turned"
  /// of turnedFrame(); forgets the commands heard so far.
  void sendGoal(const geometry_msgs::PoseStamped& base, double distance, double bearing, bool in_turned = false) {
    const geometry_msgs::Quaternion& q = base.pose.orientation;
    const double yaw = std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
    geometry_msgs::PoseStamped goal;
    goal.header.frame_id = "map";
    goal.header.stamp = ros::Time::now();
    goal.pose.position.x = base.pose.position.x + distance * std::cos(yaw + bearing);
    goal.pose.position.y = base.pose.position.y + distance * std::sin(yaw + bearing);
    goal.pose.orientation.w = 1;
    if (in_turned) {
      goal.header.frame_id = "turned";
      goal.pose.position.x = 10 - goal.pose.position.x;
      goal.pose.position.y = -goal.pose.position.y;
    }
    waitForSubscriber(goal_pub_);
    forget();
    goal_pub_.publish(goal);
  }
  /// map -> "turned" on TF: half a turn about z, 10 m along map's x.
  static geometry_msgs::TransformStamped turnedFrame() {
    geometry_msgs::TransformStamped t;
    t.header.frame_id = "map";
    t.child_frame_id = "turned";
    t.transform.translation.x = 10;
    t.transform.rotation.z = 1;
    return t;
  }
  void cancel() {
    waitForSubscriber(cancel_pub_);
    forget();
    cancel_pub_.publish(std_msgs::Empty());
  }
  std::vector<geometry_msgs::Twist> commands() {
    std::lock_guard<std::mutex> lock(mutex_);
    return commands_;
  }
  void forget() {
    std::lock_guard<std::mutex> lock(mutex_);
    commands_.clear();
  }

 private:
  static void waitForSubscriber(const ros::Publisher& pub) {
    for (int i = 0; i < 100 && pub.getNumSubscribers() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_GT(pub.getNumSubscribers(), 0u) << pub.getTopic();
  }

  std::mutex mutex_;
  std::vector<geometry_msgs::Twist> commands_;
  ros::Subscriber cmd_sub_;
  ros::Publisher goal_pub_, cancel_pub_;
};

// Every command within the TurtleBot3 Burger's limits (servo/unicycle.h), in the plane.
void expectWithinBurgerLimits(const std::vector<geometry_msgs::Twist>& commands) {
  for (const geometry_msgs::Twist& c : commands) {
    EXPECT_LE(std::abs(c.linear.x), 0.22 + 1e-9);
    EXPECT_LE(std::abs(c.angular.z), 2.84 + 1e-9);
    EXPECT_EQ(c.linear.y, 0);
    EXPECT_EQ(c.linear.z, 0);
    EXPECT_EQ(c.angular.x, 0);
    EXPECT_EQ(c.angular.y, 0);
  }
}

}  // namespace

// ~goal drives the base (here the synthetic camera's, which does not obey): nothing on
// cmd_vel before a goal; a goal straight ahead gives forward commands; one far to the left
// or right a turn in place that way (the camera turns by about 10 degrees over the
// sequence, the servo hands over to the approach within 10 degrees of the bearing: 90
// degrees off stays a turn; the one on the right is given in another frame, through TF);
// ~cancel gives one zero command and then nothing; so do ~reset and the shutdown.
TEST(RosNode, GoalDrivesCmdVelTowardsItAndCancelStopsIt) {
  constexpr int kStart = 50, kPart = 40;
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string folder = test::syntheticSequence(synth::SceneKind::kStatic, kStart + 4 * kPart);
  const std::string scratch = test::scratchDir("rosnode_goal");
  // The goals are sent before each part is played, and CameraPlayer::play waits for the
  // node's subscriptions before it sends frames: the stop when no frame comes
  // (~frame_timeout, GoalFollower's test) is kept out of the way.
  NodeProcess node(scratch + "/node", {"_no_dense:=true", "_frame_timeout:=120"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  GoalClient client;
  auto lastBase = [&] {
    std::lock_guard<std::mutex> lock(player.mutex);
    return player.last_base;
  };
  auto poses = [&] {
    std::lock_guard<std::mutex> lock(player.mutex);
    return player.latency_ms.size();
  };
  Play part;
  player.play(folder, kStart, part);
  ASSERT_EQ(lastBase().header.frame_id, "map") << "the base was tracked";
  EXPECT_TRUE(client.commands().empty()) << "no goal: nothing on cmd_vel";

  tf2_ros::StaticTransformBroadcaster tf_static;
  tf_static.sendTransform(GoalClient::turnedFrame());
  struct Leg {
    const char* name;
    double bearing;  // of the goal from the base heading, radians
    bool in_turned;  // the goal in a frame TF links to map, not in map
  };
  for (const Leg& leg : {Leg{"ahead", 0.0, false}, Leg{"left", M_PI / 2, false}, Leg{"right", -M_PI / 2, true}}) {
    client.sendGoal(lastBase(), 5.0, leg.bearing, leg.in_turned);
    const size_t poses_before = poses();
    part.skip += part.skip == 0 ? kStart : kPart;
    player.play(folder, kPart, part);
    const std::vector<geometry_msgs::Twist> commands = client.commands();
    EXPECT_GE(commands.size(), 3u) << leg.name;
    EXPECT_EQ(commands.size(), poses() - poses_before) << leg.name << ": a command per tracked frame";
    expectWithinBurgerLimits(commands);
    double v_min = 1e9, v_max = -1e9, w_min = 1e9, w_max = -1e9;
    for (const geometry_msgs::Twist& c : commands) {
      v_min = std::min(v_min, c.linear.x);
      v_max = std::max(v_max, c.linear.x);
      w_min = std::min(w_min, c.angular.z);
      w_max = std::max(w_max, c.angular.z);
      if (leg.bearing == 0) {
        EXPECT_GT(c.linear.x, 0) << leg.name;
      } else {
        EXPECT_EQ(c.linear.x, 0) << leg.name << ": a turn in place";
        EXPECT_GT(c.angular.z * leg.bearing, 0) << leg.name << ": turning towards the goal";
      }
    }
    std::printf("[figures] node goal %s: %zu commands for %d frames sent, %zu poses; v %.3f to %.3f m/s, w %.4f to %.4f "
                "rad/s\n", leg.name, commands.size(), kPart, poses() - poses_before, v_min, v_max, w_min, w_max);
  }
  client.cancel();
  for (int i = 0; i < 40 && client.commands().empty(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const std::vector<geometry_msgs::Twist> stop = client.commands();
  ASSERT_EQ(stop.size(), 1u) << "one zero command on cancel";
  EXPECT_EQ(stop[0].linear.x, 0);
  EXPECT_EQ(stop[0].angular.z, 0);
  part.skip = kStart;  // the frames again: tracked, and no goal any more
  player.play(folder, kPart, part);
  EXPECT_EQ(client.commands().size(), 1u) << "nothing after the cancel";

  // ~reset drops the goal with the map it was given in: one zero command.
  client.sendGoal(lastBase(), 5.0, M_PI / 2);
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("/plslam/reset", reset));
  for (int i = 0; i < 40 && client.commands().empty(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const std::vector<geometry_msgs::Twist> after_reset = client.commands();
  ASSERT_EQ(after_reset.size(), 1u) << "one zero command on reset";
  EXPECT_EQ(after_reset[0].linear.x, 0);
  EXPECT_EQ(after_reset[0].angular.z, 0);

  // Shutdown while driving: the last command is a zero.
  part.skip = kStart + kPart;
  player.play(folder, kPart / 2, part);  // a new map
  client.sendGoal(lastBase(), 5.0, M_PI / 2);
  part.skip += kPart / 2;
  player.play(folder, kPart / 2, part);
  EXPECT_EQ(node.stop(), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const std::vector<geometry_msgs::Twist> before_shutdown = client.commands();
  ASSERT_GE(before_shutdown.size(), 2u) << "driving, then the stop";
  EXPECT_NE(before_shutdown.front().angular.z, 0);
  EXPECT_EQ(before_shutdown.back().linear.x, 0);
  EXPECT_EQ(before_shutdown.back().angular.z, 0) << "a zero command at shutdown";
}

namespace {

// The camera `distance` metres in front of the tag of `room` (on the east wall), level,
// looking at its centre.
SE3 facingTheTag(const TagRoom& room, double distance) {
  Eigen::Matrix3d R_room_c;  // optical z along the room's +x (towards the wall), x to -y, y down
  R_room_c << 0, 0, 1,  //
      -1, 0, 0,         //
      0, -1, 0;
  const Eigen::Vector3d centre = room.tagPose().translation();
  return SE3(Eigen::Quaterniond(R_room_c), centre - Eigen::Vector3d(distance, 0, 0));
}

// What the node sends on /cmd_vel once its tag goal reaches it.
std::vector<geometry_msgs::Twist> waitForCommands(GoalClient& client, size_t count) {
  for (int i = 0; i < 60 && client.commands().size() < count; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return client.commands();
}

// Waits until no command has come for half a second (at most 20 s): the node has worked
// through the images queued so far, so a command heard later answers what the test does next.
void waitForQuiet(GoalClient& client) {
  size_t heard = client.commands().size();
  for (int quiet = 0, i = 0; quiet < 10 && i < 400; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const size_t now = client.commands().size();
    quiet = now == heard ? quiet + 1 : 0;
    heard = now;
  }
}

}  // namespace

// ~tag_goal drives the base to the tag's standoff with the tag servo on the colour images
// (the camera, TagRoom's, does not obey: the views are rendered at fixed poses): nothing
// before the tag goal; at 1.2 m from the tag, forward within the limits and no turn (it is
// straight ahead); at the standoff (0.5 m), one zero command and the tag goal is over;
// a new tag goal and ~cancel: one zero command, then nothing.
TEST(RosNode, TagGoalDrivesTowardsTheTagAndStopsAtTheStandoff) {
  test::RosMaster master;
  ASSERT_TRUE(master.ok()) << master.why();
  const std::string scratch = test::scratchDir("rosnode_tag");
  const TagRoom room(TagRoom::onEastWall(-0.8, 0.15));  // where test_servo_slam detects it: a shelf hides y = 0
  // A generous ~frame_timeout: the pauses of this test between the parts are not what it is about.
  NodeProcess node(scratch + "/node", {"_no_dense:=true", "_frame_timeout:=5"});
  ASSERT_TRUE(node.started());
  CameraPlayer player;
  GoalClient client;
  ros::NodeHandle nh;
  ros::Publisher tag_goal = nh.advertise<std_msgs::Int32>("/plslam/tag_goal", 1);
  auto sendTagGoal = [&](int id) {
    for (int i = 0; i < 100 && tag_goal.getNumSubscribers() == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_GT(tag_goal.getNumSubscribers(), 0u);
    client.forget();
    std_msgs::Int32 msg;
    msg.data = id;
    tag_goal.publish(msg);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // it reaches the node before the frames
  };

  player.playViews(room, facingTheTag(room, 1.2), 15);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_TRUE(client.commands().empty()) << "no tag goal: nothing on cmd_vel";

  sendTagGoal(room.options().tag_id);
  player.playViews(room, facingTheTag(room, 1.2), 30);
  const std::vector<geometry_msgs::Twist> approach = waitForCommands(client, 20);
  EXPECT_GE(approach.size(), 20u) << "a command per image, the tag seen in most";
  expectWithinBurgerLimits(approach);
  size_t forward = 0;
  for (const geometry_msgs::Twist& c : approach) {
    forward += c.linear.x > 0;
    EXPECT_LT(std::abs(c.angular.z), 0.2) << "the tag is straight ahead";
  }
  EXPECT_GE(forward, approach.size() * 3 / 4) << "approaching (a missed detection gives a zero)";
  std::printf("[figures] node tag goal at 1.2 m: %zu commands for 30 images, %zu forward, first v %.3f m/s\n",
              approach.size(), forward, approach.empty() ? 0.0 : approach.front().linear.x);

  waitForQuiet(client);
  client.forget();
  player.playViews(room, facingTheTag(room, 0.5), 20);
  const std::vector<geometry_msgs::Twist> at_standoff = waitForCommands(client, 1);
  ASSERT_GE(at_standoff.size(), 1u);
  EXPECT_EQ(at_standoff.back().linear.x, 0);
  EXPECT_EQ(at_standoff.back().angular.z, 0);
  // The first image seen at the standoff ends it: at most a few zeros of missed detections before.
  for (const geometry_msgs::Twist& c : at_standoff) EXPECT_EQ(c.linear.x, 0);
  client.forget();
  player.playViews(room, facingTheTag(room, 1.2), 10);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_TRUE(client.commands().empty()) << "the tag goal is over: nothing more";

  // A new tag goal, then ~cancel: one zero command and nothing after it.
  sendTagGoal(room.options().tag_id);
  player.playViews(room, facingTheTag(room, 1.2), 10);
  EXPECT_FALSE(waitForCommands(client, 5).empty());
  waitForQuiet(client);  // a command for a queued image after the cancel would be a race, not a bug
  client.cancel();
  const std::vector<geometry_msgs::Twist> stop = waitForCommands(client, 1);
  ASSERT_EQ(stop.size(), 1u) << "one zero command on cancel";
  EXPECT_EQ(stop[0].linear.x, 0);
  EXPECT_EQ(stop[0].angular.z, 0);
  player.playViews(room, facingTheTag(room, 1.2), 10);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(client.commands().size(), 1u) << "nothing after the cancel";

  // Shutdown while approaching: the last command is a zero.
  sendTagGoal(room.options().tag_id);
  player.playViews(room, facingTheTag(room, 1.2), 10);
  node.stop();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const std::vector<geometry_msgs::Twist> before_shutdown = client.commands();
  ASSERT_GE(before_shutdown.size(), 2u) << "driving, then the stop";
  EXPECT_EQ(before_shutdown.back().linear.x, 0);
  EXPECT_EQ(before_shutdown.back().angular.z, 0) << "a zero command at shutdown";
}
