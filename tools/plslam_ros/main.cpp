// plslam_ros: point-line RGB-D SLAM as a ROS 1 node (see ros_node.h and README "Under ROS").
#include <ros/ros.h>
#include <signal.h>
#include <unistd.h>

#include <exception>
#include <thread>

#include "core/allocator.h"
#include "core/log.h"
#include "ros_node.h"

int main(int argc, char** argv) {
  plslam::keepFreedMemoryForReuse();  // before any thread starts
  // SIGINT and SIGTERM are taken by sigwait below, on this thread; blocked before any
  // thread starts, so roscpp's and the SLAM threads inherit the mask and never see them.
  // A shell that starts the node in the background leaves SIGINT ignored, and an ignored
  // signal never reaches sigwait: take the default disposition back first.
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  ros::init(argc, argv, "plslam", ros::init_options::NoSigintHandler);
  try {
    ros::NodeHandle nh, pnh("~");
    plslam::setLogLevel(plslam::parseLogLevel(pnh.param<std::string>("log_level", "warn")));
    plslam::ros1::RosNode node(nh, pnh, plslam::ros1::NodeSettings::fromParameters(pnh));
    ros::AsyncSpinner spinner(2);
    spinner.start();
    // A shutdown asked through ROS (rosnode kill, the master going away) ends the node the
    // same way as SIGTERM: wake the sigwait below.
    std::thread([] {
      ros::waitForShutdown();
      kill(getpid(), SIGTERM);
    }).detach();
    int signal = 0;
    sigwait(&stop_signals, &signal);
    ROS_INFO("plslam_ros: %s: finishing and writing the outputs", signal == SIGINT ? "SIGINT" : "SIGTERM");
    const bool wrote = node.finish();
    if (!wrote) ROS_WARN("plslam_ros: no frame was tracked: no outputs written");
    spinner.stop();
    ros::shutdown();
    return wrote ? 0 : 1;
  } catch (const std::exception& e) {
    ROS_FATAL("plslam_ros: %s", e.what());
    ros::shutdown();
    return 2;
  }
}
