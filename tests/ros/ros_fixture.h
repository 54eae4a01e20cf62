// What the ROS tests share: a private rosmaster on 127.0.0.1 and a free port (never any
// other address), and a synthetic sequence written as a bag with the rosbag C++ API.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace plslam::test {

/// `rosmaster --core -p <free port>` on 127.0.0.1, started by the constructor (which also
/// sets ROS_MASTER_URI, ROS_IP and ROS_HOSTNAME in this process's environment, so children
/// and ros::init find it) and stopped by the destructor. ok() is false (with why()) when
/// it could not be started.
class RosMaster {
 public:
  RosMaster();
  ~RosMaster();
  RosMaster(const RosMaster&) = delete;
  RosMaster& operator=(const RosMaster&) = delete;
  bool ok() const { return pid_ > 0 && why_.empty(); }
  const std::string& why() const { return why_; }
  int port() const { return port_; }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  std::string why_;
};

/// A port on 127.0.0.1 that was free a moment ago (bound to port 0, then released).
int freeLocalPort();

/// Sends `signal` to the child `pid` and reaps it: its wait status, or nullopt when it had not
/// exited `timeout_s` seconds later and was killed (SIGKILL) and reaped.
std::optional<int> stopChild(pid_t pid, int signal, int timeout_s);

/// The layout of a bag written by writeBagFromFolder.
enum class BagLayout {
  kTum,        ///< /camera/rgb/image_color rgb8, /camera/depth/image 32FC1 metres, /camera/rgb/camera_info
  kRealSense,  ///< /camera/color/image_raw rgb8, /camera/aligned_depth_to_color/image_raw 16UC1 mm, /camera/color/camera_info
};
/// Writes the frames of the TUM folder `folder` (with its camera.xml) into `bag_path`,
/// stamped as in the folder. Returns the number of frames written.
int writeBagFromFolder(const std::string& folder, const std::string& bag_path, BagLayout layout);

}  // namespace plslam::test
