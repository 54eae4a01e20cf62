#include "ros_fixture.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <rosbag/bag.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "camera/camera_file.h"
#include "io/dataset.h"
#include "ros1/msg_convert.h"

namespace plslam::test {

namespace {

bool acceptsConnections(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
  close(fd);
  return ok;
}

}  // namespace

int freeLocalPort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = 0;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
  socklen_t len = sizeof(addr);
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  close(fd);
  return ntohs(addr.sin_port);
}

RosMaster::RosMaster() {
  port_ = freeLocalPort();
  const std::string uri = "http://127.0.0.1:" + std::to_string(port_);
  setenv("ROS_MASTER_URI", uri.c_str(), 1);
  setenv("ROS_IP", "127.0.0.1", 1);
  setenv("ROS_HOSTNAME", "127.0.0.1", 1);
  // Logs of the master and nodes go to a scratch folder, not ~/.ros.
  setenv("ROS_HOME", "/tmp/plslam_tests/ros_home", 1);
  pid_ = fork();
  if (pid_ == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);  // a crashed test leaves no master holding ctest's pipe
    const std::string port = std::to_string(port_);
    execlp("rosmaster", "rosmaster", "--core", "-p", port.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  if (pid_ < 0) {
    why_ = "fork failed";
    return;
  }
  for (int i = 0; i < 100; ++i) {
    if (acceptsConnections(port_)) return;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      why_ = "rosmaster exited at start (status " + std::to_string(WEXITSTATUS(status)) + ")";
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  why_ = "rosmaster did not listen on port " + std::to_string(port_) + " within 10 s";
}

RosMaster::~RosMaster() {
  // SIGTERM, not SIGINT: a test started in the background inherits SIGINT ignored.
  if (pid_ > 0) stopChild(pid_, SIGTERM, 5);
}

std::optional<int> stopChild(pid_t pid, int signal, int timeout_s) {
  kill(pid, signal);
  int status = 0;
  for (int i = 0; i < timeout_s * 10; ++i) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return std::nullopt;
}

int writeBagFromFolder(const std::string& folder, const std::string& bag_path, BagLayout layout) {
  const PinholeCamera camera = loadCameraFile(folder + "/camera.xml");
  TumDataset dataset = TumDataset::open(folder, camera);
  const bool tum = layout == BagLayout::kTum;
  const std::string colour_topic = tum ? "/camera/rgb/image_color" : "/camera/color/image_raw";
  const std::string depth_topic = tum ? "/camera/depth/image" : "/camera/aligned_depth_to_color/image_raw";
  const std::string info_topic = tum ? "/camera/rgb/camera_info" : "/camera/color/camera_info";
  rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
  sensor_msgs::CameraInfo info = ros1::infoFromCamera(camera);
  RgbdFrame frame;
  int n = 0;
  while (dataset.next(&frame)) {
    const ros::Time stamp = ros1::toRosTime(frame.t_ns);
    sensor_msgs::Image colour = ros1::bgrToImage(frame.bgr, "rgb8");
    sensor_msgs::Image depth = ros1::depthToImage(frame.depth_m, !tum);
    colour.header.stamp = depth.header.stamp = info.header.stamp = stamp;
    colour.header.seq = depth.header.seq = info.header.seq = n;
    colour.header.frame_id = depth.header.frame_id = info.header.frame_id = "camera_color_optical_frame";
    // Record times a little after the stamps, in the order a recorder sees them.
    bag.write(info_topic, stamp + ros::Duration(0.001), info);
    bag.write(colour_topic, stamp + ros::Duration(0.002), colour);
    bag.write(depth_topic, stamp + ros::Duration(0.003), depth);
    ++n;
  }
  bag.close();
  return n;
}

}  // namespace plslam::test
