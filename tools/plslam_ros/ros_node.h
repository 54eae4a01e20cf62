// plslam_ros: the ROS 1 adapter over the transport-neutral LiveSession
// (session/live_session.h). It subscribes, converts, pushes frames, and publishes what
// the session reports; the SLAM, the configuration (session/run_config.h), the frame
// conventions (session/robot_frames.h) and the outputs are the session's. A ROS 2 node
// would be a sibling of this file with the same shape.
//
// Velocity out: a goal on ~goal drives the base there with the pose servo on the SLAM base
// pose (servo/goal_follower.h, which holds the rules: nothing on cmd_vel without a goal, one
// zero command when the goal is reached, tracking is lost, on ~cancel, ~reset and shutdown).
// A tag id on ~tag_goal drives the base to the standoff in front of that AprilTag with the
// tag servo on its detections in the colour images (servo/tag_follower.h, the same rules; a
// missed detection holds the base still). One drives at a time: a goal replaces a tag goal
// and the other way round.
//
// Thread safety: the subscriber, timer and service callbacks run on the spinner's threads;
// publishing from the SLAM thread goes through roscpp publishers, which are thread-safe.
// The session pointer is set once (at the camera_info, or with ~calib at the first image
// pair; startSession under start_mutex_) under session_mutex_. The services (save_map,
// reset, localize) call the session, which applies them between two frames. The goal
// follower is shared by the SLAM thread (a command per frame) and the goal, cancel and reset
// callbacks, under follower_mutex_; so is the tag follower, fed by the image callback (the
// detection itself runs outside that lock, under detector_mutex_).
#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Empty.h>
#include <std_msgs/Int32.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "core/json.h"
#include "servo/goal_follower.h"
#include "servo/tag_follower.h"
#include "servo_sim/tag_pose.h"
#include "session/live_session.h"
#include "session/robot_frames.h"

namespace plslam::ros1 {

/// The node's parameters (private namespace, ~name); see README "Under ROS".
struct NodeSettings {
  RunSwitches switches;            ///< config, map, localize, sequential, no_lines, no_dynamic, no_loop, segmenter,
                                   ///< base (parameter camera_to_base: `plslam calib base` file; empty: from TF, else opticalToBase())
  std::string calib;               ///< camera file; empty: the camera_info
  std::string out = "plslam_ros_out";  ///< where the save service and the shutdown write the outputs
  std::string map_frame = "map", odom_frame, base_frame = "base_footprint";
  double tf_wait_s = 1.0;          ///< without a camera-to-base file: how long the start waits for base_frame -> camera on TF
  SessionOptions session;          ///< queue, drop_frames, map_frame_keyframes
  bool exact_sync = false;         ///< pair colour and depth by equal stamps instead of ApproximateTime
  int sync_queue = 10;             ///< message_filters queue size
  double sparse_period_s = 1.0;    ///< period of the sparse map topics
  bool publish_tf = true;
  bool dense = true;               ///< dense products while running (published, written to out) and at shutdown
  GoalFollowerOptions follow;      ///< max_linear, max_angular (TurtleBot3 Burger), goal_tolerance, goal_yaw_tolerance, frame_timeout
  TagFollowerOptions tag_follow;   ///< tag_standoff; the limits and frame_timeout are follow's
  double tag_size = 0.25;          ///< edge of the tags' black border, metres (TagRoom's)

  static NodeSettings fromParameters(const ros::NodeHandle& pnh);
};

class RosNode {
 public:
  RosNode(ros::NodeHandle nh, ros::NodeHandle pnh, NodeSettings settings);
  ~RosNode();
  /// Stops taking frames, ends the session and writes the outputs, as `plslam run` does at
  /// its end. Returns false when no frame was ever tracked (nothing written).
  bool finish();

 private:
  using Image = sensor_msgs::Image;
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<Image, Image>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Image>;
  using ApproxSync = message_filters::Synchronizer<ApproxPolicy>;
  using ExactSync = message_filters::Synchronizer<ExactPolicy>;

  /// Starts the session once the camera is known (at the camera_info, or with ~calib at the
  /// first image pair); `camera_frame` (the colour frame_id) is where the camera-to-base
  /// transform is looked up on TF. Once.
  void startSession(const std::string& camera_frame);
  /// base_frame -> camera_frame on TF, waiting up to tf_wait_s; none when not there.
  std::optional<SE3> cameraToBaseFromTf(const std::string& camera_frame);
  void onCameraInfo(const sensor_msgs::CameraInfoConstPtr& info);
  void onImages(const sensor_msgs::ImageConstPtr& colour, const sensor_msgs::ImageConstPtr& depth);
  void onFrame(const FrameOutcome& frame);
  void revisePath(const Trajectory& corrected, const SE3& T_map_world);  // SLAM thread
  void publishTransform(const SE3& T_map_base, const std_msgs::Header& header);
  void onSparseTimer(const ros::WallTimerEvent&);
  void onMaps(const LiveMapsUpdate& update);
  bool onSave(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  /// After a reset: empty sparse and dense maps on the latched topics.
  void clearMaps();
  bool onLocalize(std_srvs::SetBool::Request& request, std_srvs::SetBool::Response& response);
  void onGoal(const geometry_msgs::PoseStampedConstPtr& goal);
  void onCancel(const std_msgs::EmptyConstPtr&);
  void onTagGoal(const std_msgs::Int32ConstPtr& tag);
  /// The tag follower's command for a colour image (image callback), when a tag goal is active.
  void followTag(const cv::Mat& bgr);
  /// T_c_tag of tag `tag_id` in `bgr`, none when not seen whole; a detector per id, made at
  /// its first use with the session's camera.
  std::optional<SE3> detectTag(int tag_id, const cv::Mat& bgr);
  /// The goal pose in the map frame: as given in it (or without a frame_id), else through TF.
  std::optional<SE3> goalInMap(const geometry_msgs::PoseStamped& goal);
  /// The follower's command for a frame (SLAM thread); base pose none when not tracked.
  void followGoal(const std::optional<SE3>& T_map_base);
  /// Stops the base when the frames stopped coming while driving.
  void onFollowerTimer(const ros::WallTimerEvent&);
  /// Drops the goal or tag goal (cancel, reset, shutdown), sending the zero command when one
  /// was driven (then true).
  bool dropGoal(const char* why);
  /// Publishes a command on cmd_vel and logs the end of a goal; under follower_mutex_.
  void sendCommand(const FollowCommand& command);
  /// The same for the tag follower's commands; under follower_mutex_.
  void sendTagCommand(const TagFollowCommand& command);
  void publishVelocity(const VelocityCommand& command);
  Json statsExtra() const;
  LiveSession* session() const;

  ros::NodeHandle nh_, pnh_;
  NodeSettings settings_;
  RobotFrames frames_;
  message_filters::Subscriber<Image> colour_sub_, depth_sub_;
  std::unique_ptr<ApproxSync> approx_sync_;
  std::unique_ptr<ExactSync> exact_sync_;
  ros::Subscriber info_sub_;
  ros::Publisher camera_pose_pub_, base_pose_pub_, path_pub_, points_pub_, lines_pub_, status_pub_;
  ros::Publisher dense_cloud_pub_, grid_pub_;
  ros::Publisher cmd_vel_pub_;
  ros::Subscriber goal_sub_, cancel_sub_, tag_goal_sub_;
  ros::ServiceServer save_srv_, reset_srv_, localize_srv_;
  ros::WallTimer sparse_timer_, follower_timer_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  std::mutex start_mutex_;              // one start, from whichever callback comes first
  std::optional<PinholeCamera> camera_; // under start_mutex_: from ~calib or the first camera_info
  std::optional<RunConfig> config_;     // under start_mutex_: made by the constructor (a bad one fails there), used by the start
  mutable std::mutex session_mutex_;
  std::unique_ptr<LiveSession> session_;
  nav_msgs::Path path_;                 // SLAM thread only
  SE3 path_T_map_world_;                // SLAM thread: the map frame path_ is drawn in
  int path_resets_ = 0;                 // SLAM thread: the session's resets when path_ was started
  std::atomic<int> before_camera_{0};   // image pairs received before the camera was known
  std::atomic<int> unconvertible_{0};   // image pairs that could not be converted
  std::atomic<bool> finishing_{false};
  std::mutex follower_mutex_;
  GoalFollower follower_;               // under follower_mutex_
  TagFollower tag_follower_;            // under follower_mutex_; at most one of the two active
  std::mutex detector_mutex_;
  std::map<int, std::unique_ptr<TagPoseDetector>> detectors_;  // under detector_mutex_: by tag id
};

}  // namespace plslam::ros1
