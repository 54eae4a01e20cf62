// plslam servo: the ViSP servo controllers of the mobile base (servo/), run in closed loop on
// ViSP's simulated unicycle with SLAM-like pose errors, sending every command to a sink
// (printed, or UDP JSON lines for a ROS bridge to cmd_vel).
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

int runServo(int argc, char** argv) {
  Args args("servo", "Drive the mobile base (TurtleBot3 Burger limits) to a goal pose or to an AprilTag with ViSP's vpServo.");
  args.option("goal", "goal pose x,y,yaw on the floor plane (metres, metres, degrees)", "0,0,0")
      .option("start", "simulated start pose x,y,yaw (metres, metres, degrees)", "0,0,0")
      .option("tag", "servo to a simulated AprilTag centred at x,y (metres, at the camera's height) instead of --goal")
      .option("standoff", "tag servo: desired camera-to-tag distance, metres", "0.5")
      .option("sink", "where commands go: print (one line each on stdout) or udp:HOST:PORT (JSON lines)", "print")
      .flag("simulate", "run the closed loop on ViSP's simulated unicycle (vpSimulatorPioneer)")
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
          "example: plslam servo --simulate --goal 1.5,0.5,90 --noise-position 0.003 --noise-rotation 0.2 --sink udp:127.0.0.1:9870");
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

  SimulationResult r;
  if (args.has("tag")) {
    const std::vector<double> xy = numbers(args.str("tag"), "tag", 2);
    TagServoOptions tag;
    tag.standoff = args.number("standoff");
    const vpHomogeneousMatrix pMo(vpTranslationVector(xy[0], xy[1], sim.bMc[2][3]), vpRotationMatrix());
    r = simulateTagServo(pMo, tag, sim, sink.get());
    std::printf("tag servo %s after %d iterations, %.2f s simulated: depth error %.2f cm, bearing %.2f deg; "
                "max |v| %.3f m/s, max |w| %.3f rad/s; final base pose %.3f %.3f m %.2f deg\n",
                r.converged ? "converged" : "did NOT converge", r.iterations, r.sim_time_s, 100 * r.position_error,
                vpMath::deg(r.yaw_error), r.max_abs_v, r.max_abs_w, r.final_pose.x, r.final_pose.y,
                vpMath::deg(r.final_pose.yaw));
    return r.converged ? 0 : 1;
  }

  const PlanarPose goal = planarOption(args, "goal");
  std::unique_ptr<PoseErrorModel> errors;
  if (args.has("slam-trajectory")) {
    if (!args.has("groundtruth")) throw ConfigError("--slam-trajectory needs --groundtruth");
    const std::vector<SE3> e = SlamPoseError::cameraErrors(readTumTrajectory(args.str("slam-trajectory")),
                                                           readTumTrajectory(args.str("groundtruth")));
    double max_t = 0, max_r = 0;
    SlamPoseError::magnitude(e, &max_t, &max_r);
    std::fprintf(stderr, "[servo] %zu SLAM pose errors, up to %.2f mm and %.3f deg\n", e.size(), 1000 * max_t,
                 vpMath::deg(max_r));
    errors = std::make_unique<SlamPoseError>(e);
  } else if (args.number("noise-position") > 0 || args.number("noise-rotation") > 0) {
    errors = std::make_unique<GaussianPoseError>(args.number("noise-position"), vpMath::rad(args.number("noise-rotation")),
                                                 static_cast<unsigned>(args.integer("seed", 0, 1 << 30)));
  }
  r = simulatePoseServo(goal, PoseServoOptions(), sim, errors.get(), sink.get());
  std::printf("goal servo %s after %d iterations, %.2f s simulated: final error %.2f cm, %.2f deg; "
              "max |v| %.3f m/s, max |w| %.3f rad/s\n",
              r.converged ? "converged" : "did NOT converge", r.iterations, r.sim_time_s, 100 * r.position_error,
              vpMath::deg(std::abs(r.yaw_error)), r.max_abs_v, r.max_abs_w);
  return r.converged ? 0 : 1;
}

}  // namespace

Command makeServoCommand() { return {"servo", "Drive the mobile base to a goal or an AprilTag (ViSP vpServo, simulated)", runServo}; }

}  // namespace plslam::cli
