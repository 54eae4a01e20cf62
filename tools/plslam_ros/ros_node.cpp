#include "ros_node.h"

#include <geometry_msgs/Twist.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "camera/camera_file.h"
#include "core/error.h"
#include "core/log.h"
#include "ros1/msg_convert.h"
#include "ros_messages.h"

namespace plslam::ros1 {

namespace {

// The follower's clock: monotonic, unlike ROS time (which a bag's clock may drive).
double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

template <typename T>
T param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback) {
  T value;
  return pnh.getParam(name, value) ? value : fallback;
}

}  // namespace

NodeSettings NodeSettings::fromParameters(const ros::NodeHandle& pnh) {
  NodeSettings s;
  RunSwitches& w = s.switches;
  w.config = param<std::string>(pnh, "config", "");
  w.map = param<std::string>(pnh, "map", "");
  w.localize = param(pnh, "localize", false);
  w.sequential = param(pnh, "sequential", false);
  w.no_lines = param(pnh, "no_lines", false);
  w.no_dynamic = param(pnh, "no_dynamic", false);
  w.no_loop = param(pnh, "no_loop", false);
  w.segmenter = param<std::string>(pnh, "segmenter", "");  // empty: the config's segmenter.backend
  w.classes = param<std::string>(pnh, "classes", "");
  w.dynamic_classes = param<std::string>(pnh, "dynamic_classes", "");
  w.allow_missing_model = param(pnh, "allow_missing_model", false);
  s.calib = param<std::string>(pnh, "calib", "");
  w.base = param<std::string>(pnh, "camera_to_base", "");
  s.out = param<std::string>(pnh, "out", s.out);
  s.map_frame = param<std::string>(pnh, "map_frame", s.map_frame);
  s.odom_frame = param<std::string>(pnh, "odom_frame", "");
  s.base_frame = param<std::string>(pnh, "base_frame", s.base_frame);
  s.tf_wait_s = param(pnh, "tf_wait", s.tf_wait_s);
  s.session.queue = param(pnh, "queue", s.session.queue);
  s.session.drop_frames = !param(pnh, "no_drop", false);
  s.session.map_frame_keyframes = param(pnh, "map_frame_keyframes", s.session.map_frame_keyframes);
  s.exact_sync = param<std::string>(pnh, "sync", "approximate") == "exact";
  s.sync_queue = param(pnh, "sync_queue", s.sync_queue);
  s.sparse_period_s = param(pnh, "sparse_period", s.sparse_period_s);
  s.publish_tf = param(pnh, "publish_tf", true);
  s.dense = !param(pnh, "no_dense", false);
  PoseServoOptions& servo = s.follow.servo;
  servo.limits.v_max = param(pnh, "max_linear", servo.limits.v_max);
  servo.limits.w_max = param(pnh, "max_angular", servo.limits.w_max);
  servo.position_tolerance = param(pnh, "goal_tolerance", servo.position_tolerance);
  servo.yaw_tolerance_deg = param(pnh, "goal_yaw_tolerance", servo.yaw_tolerance_deg);
  s.follow.frame_timeout_s = param(pnh, "frame_timeout", s.follow.frame_timeout_s);
  s.tag_follow.servo.limits = servo.limits;
  s.tag_follow.frame_timeout_s = s.follow.frame_timeout_s;
  s.tag_follow.servo.standoff = param(pnh, "tag_standoff", s.tag_follow.servo.standoff);
  s.tag_size = param(pnh, "tag_size", s.tag_size);
  s.session.live_maps = s.dense;
  s.session.maps_dir = s.out;
  if (s.session.queue < 1 || s.sync_queue < 1 || s.sparse_period_s <= 0 || s.session.map_frame_keyframes < 1)
    throw ConfigError("plslam_ros: queue, sync_queue and map_frame_keyframes must be >= 1, sparse_period > 0");
  if (servo.limits.v_max <= 0 || servo.limits.w_max <= 0 || servo.position_tolerance <= 0 ||
      servo.yaw_tolerance_deg <= 0 || s.follow.frame_timeout_s <= 0)
    throw ConfigError("plslam_ros: max_linear, max_angular, goal_tolerance, goal_yaw_tolerance and frame_timeout must be > 0");
  if (!(s.tag_follow.servo.standoff > 0) || !(s.tag_size > 0))
    throw ConfigError("plslam_ros: tag_standoff and tag_size must be > 0");
  return s;
}

RosNode::RosNode(ros::NodeHandle nh, ros::NodeHandle pnh, NodeSettings settings)
    : nh_(nh), pnh_(pnh), settings_(std::move(settings)), tf_listener_(tf_buffer_), follower_(settings_.follow),
      tag_follower_(settings_.tag_follow) {
  config_ = makeRunConfig(settings_.switches, "plslam_ros: effective configuration");
  camera_pose_pub_ = pnh_.advertise<geometry_msgs::PoseStamped>("camera_pose", 10);
  base_pose_pub_ = pnh_.advertise<geometry_msgs::PoseStamped>("base_pose", 10);
  path_pub_ = pnh_.advertise<nav_msgs::Path>("path", 1, true);
  points_pub_ = pnh_.advertise<sensor_msgs::PointCloud2>("sparse_points", 1, true);
  lines_pub_ = pnh_.advertise<visualization_msgs::Marker>("sparse_lines", 1, true);
  status_pub_ = pnh_.advertise<diagnostic_msgs::DiagnosticArray>("status", 10);
  dense_cloud_pub_ = pnh_.advertise<sensor_msgs::PointCloud2>("dense_cloud", 1, true);
  grid_pub_ = pnh_.advertise<nav_msgs::OccupancyGrid>("grid", 1, true);
  // cmd_vel in the node's namespace, as the TurtleBot3 bringup listens (remappable).
  cmd_vel_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel", 10);
  goal_sub_ = pnh_.subscribe("goal", 1, &RosNode::onGoal, this);
  cancel_sub_ = pnh_.subscribe("cancel", 1, &RosNode::onCancel, this);
  tag_goal_sub_ = pnh_.subscribe("tag_goal", 1, &RosNode::onTagGoal, this);
  follower_timer_ = nh_.createWallTimer(ros::WallDuration(0.1), &RosNode::onFollowerTimer, this);
  save_srv_ = pnh_.advertiseService("save_map", &RosNode::onSave, this);
  reset_srv_ = pnh_.advertiseService("reset", &RosNode::onReset, this);
  localize_srv_ = pnh_.advertiseService("localize", &RosNode::onLocalize, this);
  sparse_timer_ = nh_.createWallTimer(ros::WallDuration(settings_.sparse_period_s), &RosNode::onSparseTimer, this);
  path_.header.frame_id = settings_.map_frame;

  colour_sub_.subscribe(nh_, "camera/color/image_raw", 5);
  depth_sub_.subscribe(nh_, "camera/aligned_depth_to_color/image_raw", 5);
  if (settings_.exact_sync) {
    exact_sync_ = std::make_unique<ExactSync>(ExactPolicy(settings_.sync_queue), colour_sub_, depth_sub_);
    exact_sync_->registerCallback(&RosNode::onImages, this);
  } else {
    approx_sync_ = std::make_unique<ApproxSync>(ApproxPolicy(settings_.sync_queue), colour_sub_, depth_sub_);
    approx_sync_->registerCallback(&RosNode::onImages, this);
  }
  if (settings_.calib.empty()) info_sub_ = nh_.subscribe("camera/color/camera_info", 1, &RosNode::onCameraInfo, this);
  else camera_ = loadCameraFile(settings_.calib);
  ROS_INFO_STREAM("plslam_ros: colour " << colour_sub_.getTopic() << ", depth " << depth_sub_.getTopic()
                                        << ", camera " << (settings_.calib.empty() ? info_sub_.getTopic() : settings_.calib)
                                        << "; outputs in " << settings_.out);
}

RosNode::~RosNode() = default;

void RosNode::startSession(const std::string& camera_frame) {
  std::lock_guard<std::mutex> start_lock(start_mutex_);
  if (session() || !camera_ || !config_) return;
  RunConfig config = std::move(*config_);
  config_.reset();
  // The mounting: the file (camera_to_base or calibration.camera_to_base, read by
  // makeRunConfig), else the robot's TF tree (robot_state_publisher's URDF), else none.
  std::string source = "a level camera at the base origin (no camera_to_base file, no " + settings_.base_frame + " -> " +
                       (camera_frame.empty() ? "(no frame_id)" : camera_frame) + " on TF)";
  if (config.options.dense.T_base_cam) {
    source = "file " + config.options.camera_to_base;
  } else if (const std::optional<SE3> from_tf = cameraToBaseFromTf(camera_frame)) {
    config.options.dense.T_base_cam = from_tf;
    source = "TF " + settings_.base_frame + " -> " + camera_frame;
  }
  if (config.options.dense.T_base_cam) frames_ = RobotFrames(*config.options.dense.T_base_cam);
  ROS_INFO("plslam_ros: camera-to-base from %s", source.c_str());
  auto session = std::make_unique<LiveSession>(*camera_, std::move(config), settings_.session);
  session->setFrameListener([this](const FrameOutcome& f) { onFrame(f); });
  session->setMapsListener([this](const LiveMapsUpdate& u) { onMaps(u); });
  session->start();
  std::lock_guard<std::mutex> lock(session_mutex_);
  session_ = std::move(session);
  ROS_INFO("plslam_ros: camera %dx%d fx %.1f fy %.1f: tracking", camera_->width, camera_->height, camera_->fx, camera_->fy);
}

std::optional<SE3> RosNode::cameraToBaseFromTf(const std::string& camera_frame) {
  if (camera_frame.empty()) return std::nullopt;
  try {
    // T_base_cam: the camera's pose in the base frame (lookupTransform(target, source)).
    const geometry_msgs::TransformStamped t =
        tf_buffer_.lookupTransform(settings_.base_frame, camera_frame, ros::Time(0), ros::Duration(settings_.tf_wait_s));
    return fromTransform(t.transform);
  } catch (const tf2::TransformException& e) {
    ROS_INFO("plslam_ros: no %s -> %s on TF within %.1f s: %s", settings_.base_frame.c_str(), camera_frame.c_str(),
             settings_.tf_wait_s, e.what());
    return std::nullopt;
  }
}

LiveSession* RosNode::session() const {
  std::lock_guard<std::mutex> lock(session_mutex_);
  return session_.get();
}

void RosNode::onCameraInfo(const sensor_msgs::CameraInfoConstPtr& info) {
  {
    std::lock_guard<std::mutex> lock(start_mutex_);
    if (camera_) return;
    camera_ = cameraFromInfo(*info);
  }
  info_sub_.shutdown();  // the intrinsics of a running System do not change
  // The colour camera_info's frame is the colour images' (the drivers stamp both alike):
  // the wait for TF happens here, before the images flow, and they are counted meanwhile.
  startSession(info->header.frame_id);
}

void RosNode::onImages(const sensor_msgs::ImageConstPtr& colour, const sensor_msgs::ImageConstPtr& depth) {
  // With ~calib there is no camera_info: the first pair starts the session with its frame.
  if (!session() && !finishing_ && !settings_.calib.empty()) startSession(colour->header.frame_id);
  LiveSession* s = session();
  if (!s || finishing_) {
    ++before_camera_;
    return;
  }
  RgbdFrame frame;
  try {
    frame.bgr = colourToBgr(*colour);
    frame.depth_m = depthToMetres(*depth);
  } catch (const Error& e) {
    ++unconvertible_;
    ROS_WARN_THROTTLE(5, "plslam_ros: image pair skipped: %s", e.what());
    return;
  }
  frame.t_ns = toNs(colour->header.stamp);
  frame.index = static_cast<int>(colour->header.seq);
  frame.name = colour_sub_.getTopic();
  const cv::Mat bgr = frame.bgr;  // shares the pixels: the session does not write them
  s->push(std::move(frame));
  followTag(bgr);
}

void RosNode::onFrame(const FrameOutcome& frame) {
  std_msgs::Header header;
  header.stamp = toRosTime(frame.t_ns);
  header.frame_id = settings_.map_frame;
  const double latency_ms = (ros::Time::now() - header.stamp).toSec() * 1000.0;
  status_pub_.publish(statusMessage(frame, session()->counts(), latency_ms, header));
  if (!frame.tracked) {
    followGoal(std::nullopt);
    return;
  }
  // The files' map frame once the session has fixed it (after its first keyframes), the
  // base at the first frame until then (session/robot_frames.h).
  const SE3 T_map_world = frame.map_frame_fixed ? frame.T_map_world : frames_.provisionalMapFrame();
  const SE3 T_map_base = frames_.T_map_base(T_map_world, frame.T_w_c);
  followGoal(T_map_base);
  if (settings_.publish_tf) publishTransform(T_map_base, header);
  geometry_msgs::PoseStamped pose;
  pose.header = header;
  pose.pose = toPose(frames_.T_map_cam(T_map_world, frame.T_w_c));
  camera_pose_pub_.publish(pose);
  pose.pose = toPose(T_map_base);
  base_pose_pub_.publish(pose);
  path_.header.stamp = header.stamp;
  if (frame.resets != path_resets_) {  // a new map: a new path
    path_.poses.clear();
    path_resets_ = frame.resets;
  }
  // After a loop correction the whole path is redrawn from the corrected poses (this
  // frame's included); otherwise it grows by this pose.
  // When the map frame was fixed since the last pose, the path is redrawn in it too.
  if (frame.revised) {
    revisePath(*frame.revised, T_map_world);
  } else {
    if (!path_.poses.empty() && (path_T_map_world_.inverse() * T_map_world).log().norm() > 1e-12) {
      const SE3 T_new_old = T_map_world * path_T_map_world_.inverse();
      for (geometry_msgs::PoseStamped& p : path_.poses) p.pose = toPose(T_new_old * fromPose(p.pose));
    }
    path_.poses.push_back(pose);
  }
  path_T_map_world_ = T_map_world;
  path_pub_.publish(path_);
}

void RosNode::revisePath(const Trajectory& corrected, const SE3& T_map_world) {
  path_.poses.clear();
  geometry_msgs::PoseStamped pose;
  pose.header.frame_id = settings_.map_frame;
  for (const StampedPose& p : corrected) {
    pose.header.stamp = toRosTime(p.t_ns);
    pose.pose = toPose(frames_.T_map_base(T_map_world, p.T_w_c));
    path_.poses.push_back(pose);
  }
}

void RosNode::publishTransform(const SE3& T_map_base, const std_msgs::Header& header) {
  geometry_msgs::TransformStamped t;
  t.header = header;
  if (settings_.odom_frame.empty()) {
    t.child_frame_id = settings_.base_frame;
    t.transform = toTransform(T_map_base);
  } else {
    // The wheel odometry owns odom -> base: publish the map -> odom that makes them agree.
    geometry_msgs::TransformStamped odom_base;
    try {
      odom_base = tf_buffer_.lookupTransform(settings_.odom_frame, settings_.base_frame, header.stamp, ros::Duration(0.1));
    } catch (const tf2::TransformException& e) {
      ROS_WARN_THROTTLE(5, "plslam_ros: no %s -> %s at the image stamp, map -> odom not published: %s",
                        settings_.odom_frame.c_str(), settings_.base_frame.c_str(), e.what());
      return;
    }
    t.child_frame_id = settings_.odom_frame;
    t.transform = toTransform(T_map_base * fromTransform(odom_base.transform).inverse());
  }
  tf_broadcaster_.sendTransform(t);
}

void RosNode::onSparseTimer(const ros::WallTimerEvent&) {
  LiveSession* s = session();
  if (!s) return;
  const SparseMapSnapshot map = s->sparseMap();
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = settings_.map_frame;
  const std::optional<MapFrame> frame = s->mapFrame();
  const SE3 T_map_world = frame ? frame->T_map_world : frames_.provisionalMapFrame();
  points_pub_.publish(pointsMessage(map, T_map_world, header));
  lines_pub_.publish(linesMessage(map, T_map_world, header));
}

void RosNode::onMaps(const LiveMapsUpdate& update) {
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = settings_.map_frame;
  // The products are in the maps' own floor-based frame (core/map_frame.h), which may not be
  // the session's yet; they are published in the node's map frame, the one of its TF and
  // sparse map: the session's fixed frame, or the provisional one before it is fixed.
  const LiveSession* s = session();
  if (!s) return;  // the maps thread can report before the session is handed over
  const std::optional<MapFrame> frame = s->mapFrame();
  const SE3 T_map_world = frame ? frame->T_map_world : frames_.provisionalMapFrame();
  const SE3 T_pub_map = T_map_world * update.frame.T_map_world.inverse();
  dense_cloud_pub_.publish(denseCloudMessage(*update.cloud, T_pub_map, header));
  if (update.grid->width > 0) grid_pub_.publish(gridMessage(*update.grid, T_pub_map, header));
}

Json RosNode::statsExtra() const {
  const SessionCounts c = session()->counts();
  return {{"ros_received", c.received},
          {"ros_processed", c.processed},
          {"ros_dropped", c.dropped},
          {"ros_before_camera", before_camera_.load()},
          {"ros_unconvertible", unconvertible_.load()}};
}

void RosNode::clearMaps() {
  // The latched maps of the dropped map would stay on until the new map's first update.
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = settings_.map_frame;
  const SparseMapSnapshot none;
  points_pub_.publish(pointsMessage(none, SE3(), header));
  lines_pub_.publish(linesMessage(none, SE3(), header));
  if (!settings_.dense) return;
  dense_cloud_pub_.publish(denseCloudMessage({}, SE3(), header));
  nav_msgs::OccupancyGrid grid;
  grid.header = header;
  grid_pub_.publish(grid);
}

bool RosNode::onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  LiveSession* s = session();
  if (!s || finishing_) {
    response.success = false;
    response.message = s ? "finishing" : "no camera yet: nothing to save";
    return true;
  }
  try {
    s->save(settings_.out, statsExtra());
    response.success = true;
    response.message = settings_.out;
  } catch (const std::exception& e) {
    response.success = false;
    response.message = e.what();
  }
  return true;
}

bool RosNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  LiveSession* s = session();
  response.success = false;
  if (!s || finishing_) {
    response.message = s ? "finishing" : "no camera yet: nothing to reset";
    return true;
  }
  try {
    dropGoal("reset");  // the goal was given in the map being dropped
    s->reset();
    clearMaps();
    response.success = true;
    response.message = "map dropped: the next frame starts a new one";
    ROS_INFO("plslam_ros: reset: %s", response.message.c_str());
  } catch (const std::exception& e) {
    response.message = e.what();
  }
  return true;
}

bool RosNode::onLocalize(std_srvs::SetBool::Request& request, std_srvs::SetBool::Response& response) {
  LiveSession* s = session();
  response.success = false;
  if (!s || finishing_) {
    response.message = s ? "finishing" : "no camera yet";
    return true;
  }
  try {
    s->setLocalization(request.data);
    response.success = true;
    response.message = request.data ? "localising: the map is kept as it is" : "mapping";
    ROS_INFO("plslam_ros: %s", response.message.c_str());
  } catch (const std::exception& e) {
    response.message = e.what();
  }
  return true;
}

void RosNode::onGoal(const geometry_msgs::PoseStampedConstPtr& goal) {
  const std::optional<SE3> T_map_goal = goalInMap(*goal);
  if (!T_map_goal) return;
  const PlanarPose planar = GoalFollower::planarGoal(*T_map_goal);
  std::lock_guard<std::mutex> lock(follower_mutex_);
  if (finishing_) return;
  tag_follower_.cancel();  // one drives at a time; the goal's commands follow at the next frame
  follower_.setGoal(planar, steadySeconds());
  ROS_INFO("plslam_ros: goal x %.3f y %.3f yaw %.1f deg in %s: driving on %s", planar.x, planar.y,
           planar.yaw * 180 / M_PI, settings_.map_frame.c_str(), cmd_vel_pub_.getTopic().c_str());
}

std::optional<SE3> RosNode::goalInMap(const geometry_msgs::PoseStamped& goal) {
  const std::string& frame = goal.header.frame_id;
  if (frame.empty() || frame == settings_.map_frame) return fromPose(goal.pose);
  try {
    // The latest transform: a goal is a place, not a moment (a goal from rviz in odom
    // means where odom puts it now).
    const geometry_msgs::TransformStamped t =
        tf_buffer_.lookupTransform(settings_.map_frame, frame, ros::Time(0), ros::Duration(0.5));
    return fromTransform(t.transform) * fromPose(goal.pose);
  } catch (const tf2::TransformException& e) {
    ROS_WARN("plslam_ros: goal ignored: no %s -> %s on TF: %s", settings_.map_frame.c_str(), frame.c_str(), e.what());
    return std::nullopt;
  }
}

void RosNode::onCancel(const std_msgs::EmptyConstPtr&) { dropGoal("cancelled"); }

void RosNode::onTagGoal(const std_msgs::Int32ConstPtr& tag) {
  // The servo needs the camera's mounting, which the session's start settles.
  if (!session()) {
    ROS_WARN("plslam_ros: tag goal %d ignored: no camera yet", tag->data);
    return;
  }
  if (tag->data < 0) {
    ROS_WARN("plslam_ros: tag goal %d ignored: not a tag36h11 id", tag->data);
    return;
  }
  std::lock_guard<std::mutex> lock(follower_mutex_);
  if (finishing_) return;
  follower_.cancel();  // one drives at a time; the tag servo's commands follow at the next image
  tag_follower_.setTarget(tag->data, frames_.T_base_cam(), steadySeconds());
  ROS_INFO("plslam_ros: tag goal %d (tag36h11, %.3f m): approaching to %.2f m, driving on %s", tag->data,
           settings_.tag_size, settings_.tag_follow.servo.standoff, cmd_vel_pub_.getTopic().c_str());
}

void RosNode::followTag(const cv::Mat& bgr) {
  int tag_id = -1;
  {
    std::lock_guard<std::mutex> lock(follower_mutex_);
    if (finishing_) return;
    tag_id = tag_follower_.tagId();
  }
  if (tag_id < 0) return;  // no tag goal: no detection cost
  const std::optional<SE3> T_c_tag = detectTag(tag_id, bgr);
  std::lock_guard<std::mutex> lock(follower_mutex_);
  // The target may have changed during the detection: this one is not about it.
  if (finishing_ || tag_follower_.tagId() != tag_id) return;
  if (const std::optional<TagFollowCommand> command = tag_follower_.update(T_c_tag, steadySeconds()))
    sendTagCommand(*command);
}

std::optional<SE3> RosNode::detectTag(int tag_id, const cv::Mat& bgr) {
  std::lock_guard<std::mutex> lock(detector_mutex_);
  std::unique_ptr<TagPoseDetector>& detector = detectors_[tag_id];
  if (!detector) {
    std::lock_guard<std::mutex> start_lock(start_mutex_);  // camera_ is set once, before the session
    detector = std::make_unique<TagPoseDetector>(*camera_, tag_id, settings_.tag_size);
  }
  return detector->detect(bgr);
}

void RosNode::followGoal(const std::optional<SE3>& T_map_base) {
  std::lock_guard<std::mutex> lock(follower_mutex_);
  if (finishing_) return;  // finish() has sent the last command
  if (const std::optional<FollowCommand> command = follower_.update(T_map_base, steadySeconds())) sendCommand(*command);
}

void RosNode::onFollowerTimer(const ros::WallTimerEvent&) {
  std::lock_guard<std::mutex> lock(follower_mutex_);
  if (finishing_) return;
  const double now = steadySeconds();
  if (const std::optional<FollowCommand> command = follower_.checkFrames(now)) sendCommand(*command);
  if (const std::optional<TagFollowCommand> command = tag_follower_.checkFrames(now)) sendTagCommand(*command);
}

bool RosNode::dropGoal(const char* why) {
  std::lock_guard<std::mutex> lock(follower_mutex_);
  const std::optional<FollowCommand> command = follower_.cancel();
  const std::optional<TagFollowCommand> tag_command = tag_follower_.cancel();
  if (!command && !tag_command) return false;
  publishVelocity(VelocityCommand());  // at most one was driving: one zero command
  ROS_INFO("plslam_ros: goal dropped (%s): zero velocity sent", why);
  return true;
}

void RosNode::publishVelocity(const VelocityCommand& command) {
  geometry_msgs::Twist twist;
  twist.linear.x = command.v;
  twist.angular.z = command.w;
  cmd_vel_pub_.publish(twist);
}

void RosNode::sendCommand(const FollowCommand& command) {
  publishVelocity(command.command);
  if (command.stop == FollowStop::kReached)
    ROS_INFO("plslam_ros: goal reached (%.3f m, %.1f deg off): stopped", command.step.position_error,
             command.step.yaw_error * 180 / M_PI);
  else if (command.stop == FollowStop::kLost)
    ROS_WARN("plslam_ros: tracking lost: stopped, the goal is dropped (send it again)");
  else if (command.stop == FollowStop::kNoFrames)
    ROS_WARN("plslam_ros: no frame for %.1f s: stopped, the goal is dropped (send it again)",
             settings_.follow.frame_timeout_s);
}

void RosNode::sendTagCommand(const TagFollowCommand& command) {
  publishVelocity(command.command);
  if (command.stop == FollowStop::kReached)
    ROS_INFO("plslam_ros: tag standoff reached (%.3f m, %.1f deg off): stopped", command.step.depth_error,
             command.step.bearing * 180 / M_PI);
  else if (command.stop == FollowStop::kLost)
    ROS_WARN("plslam_ros: tag not seen for %.1f s: stopped, the tag goal is dropped (send it again)",
             settings_.tag_follow.frame_timeout_s);
  else if (command.stop == FollowStop::kNoFrames)
    ROS_WARN("plslam_ros: no image for %.1f s: stopped, the tag goal is dropped (send it again)",
             settings_.tag_follow.frame_timeout_s);
}

bool RosNode::finish() {
  {
    std::lock_guard<std::mutex> lock(follower_mutex_);
    finishing_ = true;
  }
  // roscpp writes to the subscribers from its own threads: give the zero command time to
  // leave before the node shuts down.
  if (dropGoal("shutdown")) ros::WallDuration(0.2).sleep();
  colour_sub_.unsubscribe();
  depth_sub_.unsubscribe();
  sparse_timer_.stop();
  LiveSession* s = session();
  if (!s) return false;
  s->stop();
  if (s->counts().tracked == 0) return false;
  s->writeOutputs(settings_.out, statsExtra(), settings_.dense);
  return true;
}

}  // namespace plslam::ros1
