// Closed-loop runs of the servo controllers on ViSP's simulated unicycle
// (vpSimulatorPioneer, its camera mounted as the robot's), with the pose measurement
// perturbed as SLAM would perturb it:
//
//   - SlamPoseError: the errors of a real SLAM run, cMc' = T_gt^-1 * T_est per frame
//     (after aligning the run's first pose to the ground truth, so the error is the drift
//     the robot would see from its start), applied in turn to the true camera pose;
//   - GaussianPoseError: independent noise on the camera position and orientation.
//
// The simulated world frame is the floor-plane frame p (z up); the SLAM map frame is the
// camera at the start, as in a real run, and the controller gets pMb through PlanarMap.
//
// The measurement is an interface so that a pose model may also be a SLAM run on images
// rendered at the true pose, and the tag's pose a detection in them (servo_sim/): a model
// that has no pose for a step (SLAM lost, tag not seen) stops the base for that step.
#pragma once

#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "core/trajectory.h"
#include "servo/pose_servo.h"
#include "servo/tag_servo.h"
#include "servo/velocity_sink.h"

namespace plslam {

/// Turns the true camera pose (in the SLAM map w, the camera at the start) into a measured
/// one; nullopt when there is no measurement at this step (the base then stops).
class PoseErrorModel {
 public:
  virtual ~PoseErrorModel() = default;
  virtual std::optional<vpHomogeneousMatrix> measure(int step, const vpHomogeneousMatrix& wMc_true) = 0;
};

/// What the tag servo sees: the tag pose cMo from the true camera pose pMc in the plane
/// frame; nullopt when the tag is not seen (the base then stops).
class TagSensor {
 public:
  virtual ~TagSensor() = default;
  virtual std::optional<vpHomogeneousMatrix> observe(int step, const vpHomogeneousMatrix& pMc_true) = 0;
};

/// Applies SLAM errors in turn, one per control step, going back and forth through the run.
class SlamPoseError : public PoseErrorModel {
 public:
  explicit SlamPoseError(std::vector<SE3> errors);
  std::optional<vpHomogeneousMatrix> measure(int step, const vpHomogeneousMatrix& wMc_true) override;
  /// The per-frame camera errors T_gt^-1 * (T_align * T_est) of a run: each estimated pose is
  /// paired with the ground truth pose closest in time (within max_dt_s); T_align maps the
  /// first paired estimate onto its ground truth. Throws DataError when fewer than two
  /// poses pair.
  static std::vector<SE3> cameraErrors(const Trajectory& estimate, const Trajectory& groundtruth, double max_dt_s = 0.01);
  /// Largest translation (metres) and rotation (radians) among the errors.
  static void magnitude(const std::vector<SE3>& errors, double* max_translation, double* max_rotation);

 private:
  std::vector<SE3> errors_;
};

class GaussianPoseError : public PoseErrorModel {
 public:
  GaussianPoseError(double sigma_position_m, double sigma_rotation_rad, unsigned seed = 1);
  std::optional<vpHomogeneousMatrix> measure(int step, const vpHomogeneousMatrix& wMc_true) override;

 private:
  double sigma_p_, sigma_r_;
  std::mt19937 rng_;
};

struct SimulationOptions {
  PlanarPose start;                   ///< initial base pose in the plane frame
  double dt = 1.0 / 30;               ///< control period = simulator sampling time, seconds
  double max_time_s = 120;            ///< give up after this much simulated time
  vpHomogeneousMatrix bMc = PlanarMap::defaultCameraMounting();  ///< the camera on the base
};

struct SimulationResult {
  bool converged = false;     ///< the controller reported done
  int iterations = 0;         ///< control steps run
  double sim_time_s = 0;      ///< simulated time
  PlanarPose final_pose;      ///< true final base pose
  double position_error = 0;  ///< true final distance to the goal (pose servo) or depth error (tag servo), metres
  double yaw_error = 0;       ///< true final heading error (pose servo) or bearing (tag servo), radians
  int blind_steps = 0;        ///< steps without a measurement (SLAM lost, tag not seen): the base stood still
  double max_abs_v = 0, max_abs_w = 0;  ///< over every command sent
  std::vector<VelocityCommand> commands;
};

/// Runs PoseServo to `goal` on the simulated base. `errors` (may be null: exact poses)
/// perturbs the SLAM pose; `sink` (may be null) receives every command.
SimulationResult simulatePoseServo(const PlanarPose& goal, const PoseServoOptions& servo, const SimulationOptions& sim,
                                   PoseErrorModel* errors = nullptr, VelocitySink* sink = nullptr);

/// Runs TagServo towards a tag at pMo (in the plane frame) on the simulated base; the tag
/// pose fed to it comes from `sensor`, the true cMo when null. position_error is the true
/// final depth error, yaw_error the true final bearing of the tag centre.
SimulationResult simulateTagServo(const vpHomogeneousMatrix& pMo, const TagServoOptions& servo,
                                  const SimulationOptions& sim, VelocitySink* sink = nullptr,
                                  TagSensor* sensor = nullptr);

}  // namespace plslam
