// Drives the unicycle base to a goal pose (x, y, yaw) on the floor, from its measured pose
// (SLAM), with ViSP's vpServo.
//
// A unicycle cannot be brought to a full pose by a smooth time-invariant feedback
// (Brockett's condition), and a linear PBVS on (x, y, yaw) would ask for the sideways
// velocity it does not have. The controller therefore runs three stages, each a vpServo
// task of the form qdot = -lambda (L cVe eJe)^+ (s - s*) with the unicycle Jacobian eJe
// (as ViSP's servoPioneer* examples):
//
//  1. turn:     when the goal lies more than turn_first_deg off the heading, turn in
//               place towards it (feature: theta-u about z of the rotation from the
//               current heading to the goal's bearing, vpFeatureThetaU; eJe = the w column).
//  2. approach: drive to the goal position. A virtual camera at the base, looking
//               forward, sees the goal point at depth Z and normalised abscissa x; the
//               features are x (vpFeaturePoint, s* = 0) and Z (vpGenericFeature, s* = 0).
//               The 2x2 task Jacobian [[x/Z, 1+x^2], [-1, -xZ]] has determinant 1, so the
//               task is never singular, and its exact inverse gives v = lambda Z (1+2x^2),
//               w = -2 lambda x: both errors decay exponentially, v vanishes with the
//               distance and w stays bounded, down to the goal point itself (where a
//               point-feature or (rho, bearing) scheme becomes singular). The gain is
//               adaptive (vpAdaptiveGain): higher near the goal to shorten the tail.
//  3. align:    at the goal position (within position_tolerance), turn in place to the
//               goal heading (vpFeatureThetaU as in 1, towards the goal yaw).
//
// Commands are saturated to the base's limits with their ratio kept (the path's
// curvature does not change). A drift away from the goal after arrival (pose noise,
// slipping) beyond reapproach_factor x the tolerance restarts the approach.
//
// Thread safety: none; one PoseServo per control loop.
#pragma once

#include <memory>
#include <string>

#include "servo/unicycle.h"

namespace plslam {

struct PoseServoOptions {
  double gain_far = 0.6;             ///< vpServo gain for large errors, 1/s
  double gain_near = 3.0;            ///< vpServo gain at zero error, 1/s (adaptive gain in between)
  double gain_slope = 15.0;          ///< adaptive gain slope at zero error
  double turn_gain = 2.0;            ///< gain of the turn and align stages, 1/s
  double position_tolerance = 0.006; ///< the approach ends this close to the goal position, metres
  double yaw_tolerance_deg = 1.0;    ///< the alignment ends this close to the goal heading, degrees
  double turn_first_deg = 60.0;      ///< turn in place first when the goal bearing is further off than this, degrees
  double turn_done_deg = 10.0;       ///< the turn stage hands over to the approach within this bearing, degrees
  double reapproach_factor = 2.5;    ///< after arrival, restart when the position error exceeds this x position_tolerance
  UnicycleLimits limits;             ///< speed limits of the base
};

enum class ServoStage { kTurn, kApproach, kAlign, kDone };
const char* toString(ServoStage stage);

/// One control step.
struct ServoStep {
  VelocityCommand command;         ///< saturated command for the base
  ServoStage stage = ServoStage::kTurn;
  double position_error = 0;       ///< distance to the goal position (as measured), metres
  double yaw_error = 0;            ///< heading minus goal heading (as measured), radians
  bool done = false;               ///< at the goal within tolerance (command is zero)
};

class PoseServo {
 public:
  PoseServo(const PlanarPose& goal, const PoseServoOptions& options = {});
  ~PoseServo();
  PoseServo(const PoseServo&) = delete;
  PoseServo& operator=(const PoseServo&) = delete;

  /// The command for the measured base pose in the plane frame (pMb).
  ServoStep update(const vpHomogeneousMatrix& pMb);
  const PlanarPose& goal() const { return goal_; }
  ServoStage stage() const { return stage_; }

 private:
  struct Tasks;
  PlanarPose goal_;
  PoseServoOptions options_;
  ServoStage stage_ = ServoStage::kTurn;
  std::unique_ptr<Tasks> tasks_;
};

}  // namespace plslam
