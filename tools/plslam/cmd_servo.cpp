// plslam servo: the ViSP servo controllers of the mobile base (servo/), run in closed loop on
// ViSP's simulated unicycle, sending every command to a sink (printed, or UDP JSON lines for
// a ROS bridge to cmd_vel). The controllers measure either the simulated truth with
// SLAM-like errors (--poses simulated) or what the camera would see: views of the synthetic
// room rendered at the true pose, tracked by plslam, the tag detected in them (--poses slam,
// servo_sim/).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include <visp3/core/vpMath.h>

#include "calibration/base_transform.h"
#include "camera/visp_conversion.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "io/trajectory_file.h"
#include "servo/simulation.h"
#include "servo_sim/rendered_sensors.h"

namespace plslam::cli {

namespace {

std::vector<double> numbers(const std::string& text, const std::string& option, size_t count) {
  std::vector<double> v;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || !end || *end != '\0' || !std::isfinite(x))
      throw ConfigError("--" + option + " '" + text + "': '" + item + "' is not a number");
    v.push_back(x);
  }
  if (v.size() != count) throw ConfigError(str("--", option, " '", text, "': expected ", count, " comma-separated numbers"));
  return v;
}

PlanarPose planarOption(const Args& args, const std::string& option) {
  const std::vector<double> v = numbers(args.str(option), option, 3);
  return {v[0], v[1], vpMath::rad(v[2])};
}

// --poses slam: the room must hold the base; the plane frame is placed in it at T_room_p.
void requireInsideRoom(const SE3& T_room_p, const PlanarPose& pose, const std::string& what) {
  const Eigen::Vector3d p = T_room_p * Eigen::Vector3d(pose.x, pose.y, 0);
  if (std::abs(p.x()) > 2.7 || std::abs(p.y()) > 2.2)
    throw ConfigError(str("--poses slam: the ", what, " ", pose.x, ",", pose.y, " lies at ", p.x(), ",", p.y(),
                          " in the synthetic room, outside its floor (x within 2.7 m, y within 2.2 m of its centre)"));
}

int runTagServo(const Args& args, const SimulationOptions& sim, VelocitySink* sink, bool rendered) {
  const std::vector<double> xy = numbers(args.str("tag"), "tag", 2);
  TagServoOptions tag;
  tag.standoff = args.number("standoff");
  const vpHomogeneousMatrix pMo(vpTranslationVector(xy[0], xy[1], sim.bMc[2][3]), vpRotationMatrix());
  SimulationResult r;
  if (rendered) {
    // The room is placed so that the tag lies on its east wall, facing the plane's -x.
    const SE3 T_room_p = planeForTagOnEastWall(xy[0], xy[1]);
    requireInsideRoom(T_room_p, sim.start, "start");
    const TagRoom room(TagRoom::onEastWall((T_room_p * Eigen::Vector3d(xy[0], xy[1], 0)).y(), sim.bMc[2][3]));
    DetectedTag sensor(room, T_room_p);
    r = simulateTagServo(pMo, tag, sim, sink, &sensor);
    std::printf("tag detected in %d of %d views\n", sensor.detections(), sensor.detections() + sensor.misses());
  } else {
    r = simulateTagServo(pMo, tag, sim, sink);
  }
  std::printf("tag servo %s after %d iterations, %.2f s simulated: depth error %.2f cm, bearing %.2f deg; "
              "max |v| %.3f m/s, max |w| %.3f rad/s; final base pose %.3f %.3f m %.2f deg\n",
              r.converged ? "converged" : "did NOT converge", r.iterations, r.sim_time_s, 100 * r.position_error,
              vpMath::deg(r.yaw_error), r.max_abs_v, r.max_abs_w, r.final_pose.x, r.final_pose.y,
              vpMath::deg(r.final_pose.yaw));
  return r.converged ? 0 : 1;
}

std::unique_ptr<PoseErrorModel> simulatedErrors(const Args& args) {
  if (args.has("slam-trajectory")) {
    if (!args.has("groundtruth")) throw ConfigError("--slam-trajectory needs --groundtruth");
    const std::vector<SE3> e = SlamPoseError::cameraErrors(readTumTrajectory(args.str("slam-trajectory")),
                                                           readTumTrajectory(args.str("groundtruth")));
    double max_t = 0, max_r = 0;
    SlamPoseError::magnitude(e, &max_t, &max_r);
    std::fprintf(stderr, "[servo] %zu SLAM pose errors, up to %.2f mm and %.3f deg\n", e.size(), 1000 * max_t,
                 vpMath::deg(max_r));
    return std::make_unique<SlamPoseError>(e);
  }
  if (args.number("noise-position") > 0 || args.number("noise-rotation") > 0)
    return std::make_unique<GaussianPoseError>(args.number("noise-position"), vpMath::rad(args.number("noise-rotation")),
                                               static_cast<unsigned>(args.integer("seed", 0, 1 << 30)));
  return nullptr;
}

int runGoalServo(const Args& args, const SimulationOptions& sim, VelocitySink* sink, bool rendered) {
  const PlanarPose goal = planarOption(args, "goal");
  SimulationResult r;
  if (rendered) {
    const SE3 T_room_p = defaultPlaneInRoom();
    requireInsideRoom(T_room_p, sim.start, "start");
    requireInsideRoom(T_room_p, goal, "goal");
    const TagRoom room(TagRoom::onEastWall(-0.8, sim.bMc[2][3]));
    // The SLAM map is the first camera frame: the camera at the start.
    SlamPoses slam(room, T_room_p * fromVisp(PlanarMap::toMatrix(sim.start) * sim.bMc), sim.dt);
    r = simulatePoseServo(goal, PoseServoOptions(), sim, &slam, sink);
    std::printf("SLAM tracked %d of %d views (%d keyframes); largest camera position error %.2f cm\n",
                slam.framesFed() - slam.framesLost(), slam.framesFed(), slam.system().stats().keyframes,
                100 * slam.maxPositionError());
  } else {
    const std::unique_ptr<PoseErrorModel> errors = simulatedErrors(args);
    r = simulatePoseServo(goal, PoseServoOptions(), sim, errors.get(), sink);
  }
  std::printf("goal servo %s after %d iterations, %.2f s simulated: final error %.2f cm, %.2f deg; "
              "max |v| %.3f m/s, max |w| %.3f rad/s\n",
              r.converged ? "converged" : "did NOT converge", r.iterations, r.sim_time_s, 100 * r.position_error,
              vpMath::deg(std::abs(r.yaw_error)), r.max_abs_v, r.max_abs_w);
  return r.converged ? 0 : 1;
}

int runServo(int argc, char** argv) {
  Args args("servo", "Drive the mobile base (TurtleBot3 Burger limits) to a goal pose or to an AprilTag with ViSP's vpServo.");
  args.option("goal", "goal pose x,y,yaw on the floor plane (metres, metres, degrees)", "0,0,0")
      .option("start", "simulated start pose x,y,yaw (metres, metres, degrees)", "0,0,0")
      .option("tag", "servo to a simulated AprilTag centred at x,y (metres, at the camera's height) instead of --goal")
      .option("standoff", "tag servo: desired camera-to-tag distance, metres", "0.5")
      .option("sink", "where commands go: print (one line each on stdout) or udp:HOST:PORT (JSON lines)", "print")
      .flag("simulate", "run the closed loop on ViSP's simulated unicycle (vpSimulatorPioneer)")
      .option("poses", "what the controller measures: simulated (the true pose, with --noise-* or --slam-trajectory "
                       "errors; the true tag pose) or slam (views of the synthetic room rendered at the true pose, "
                       "320x240: the goal servo uses plslam's pose of them, the tag servo the tag detected in them)",
              "simulated")
      .option("noise-position", "simulated SLAM position noise, metres (standard deviation)", "0")
      .option("noise-rotation", "simulated SLAM rotation noise, degrees (standard deviation)", "0")
      .option("seed", "noise seed", "1")
      .option("slam-trajectory", "use the pose errors of this SLAM run (TUM trajectory; needs --groundtruth)")
      .option("groundtruth", "the ground truth of --slam-trajectory (TUM trajectory)")
      .option("base", "camera-to-base file of plslam calib base: the camera's mounting on the base (default: a level "
                      "camera 0.10 m ahead of the wheel axis, 0.15 m above the floor)")
      .option("rate", "control rate, Hz", "30")
      .option("max-time", "give up after this much simulated time, seconds", "120")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .epilog(
          "The goal controller turns towards the goal, drives to it (vpServo on the goal point's image abscissa and\n"
          "depth in a virtual forward camera, with the unicycle Jacobian), then turns to the goal heading; commands are\n"
          "saturated to v 0.22 m/s, w 2.84 rad/s with their ratio kept. See src/servo/pose_servo.h.\n"
          "Exit status: 0 converged, 1 not converged within --max-time, 2 bad options.\n\n"
          "With --poses slam the plane frame's origin is at (-1.2, 0.3) in the synthetic room (synth/scene.h), x east; with\n"
          "--tag the room is placed so that the tag (tag36h11 id 0, 0.25 m) is on its east wall, facing the plane's -x.\n"
          "Lost tracking or no tag in view: the base stops for that step.\n\n"
          "example: plslam servo --simulate --goal 1.5,0.5,90 --noise-position 0.003 --noise-rotation 0.2 --sink udp:127.0.0.1:9870\n"
          "         plslam servo --simulate --poses slam --goal 1.5,0.5,90");
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));
  if (!args.has("simulate"))
    throw ConfigError(
        "plslam servo: only --simulate is available: on the robot the controller needs live SLAM poses, and live "
        "capture needs ViSP with librealsense2 (see plslam live --help)");

  SimulationOptions sim;
  sim.start = planarOption(args, "start");
  const double rate = args.number("rate");
  if (!(rate > 0)) throw ConfigError("--rate must be positive");
  sim.dt = 1.0 / rate;
  sim.max_time_s = args.number("max-time");
  // The measured mounting (the same file as plslam run --base) instead of the placeholder.
  if (args.has("base")) sim.bMc = toVisp(calib::loadCameraToBase(args.str("base")));
  std::unique_ptr<VelocitySink> sink = makeVelocitySink(args.str("sink"), std::cout);

  const std::string poses = args.str("poses");
  if (poses != "simulated" && poses != "slam") throw ConfigError("--poses '" + poses + "': expected simulated or slam");
  const bool rendered = poses == "slam";
  if (rendered && (args.has("slam-trajectory") || args.number("noise-position") > 0 || args.number("noise-rotation") > 0))
    throw ConfigError("--poses slam measures the pose by SLAM on rendered views: --noise-* and --slam-trajectory "
                      "are for --poses simulated");
  return args.has("tag") ? runTagServo(args, sim, sink.get(), rendered) : runGoalServo(args, sim, sink.get(), rendered);
}

}  // namespace

Command makeServoCommand() { return {"servo", "Drive the mobile base to a goal or an AprilTag (ViSP vpServo, simulated)", runServo}; }

}  // namespace plslam::cli
