// Servoes the base to stand in front of an AprilTag seen by its camera, as ViSP's
// servoPioneerPoint2DDepth example: the features are the abscissa x of the tag centre in
// the image (vpFeaturePoint, s* = 0: the tag straight ahead) and log(Z / Z*) of its depth
// (vpFeatureDepth, Z* = the standoff), in a vpServo task qdot = -lambda (L cVe eJe)^+ e with
// the camera's mounting on the base (cVe) and the unicycle Jacobian (eJe). The camera must
// be ahead of the wheel axis (as on a Burger): the task is then never singular.
//
// Input: the tag pose in the camera frame (cMo, e.g. from vpDetectorAprilTag::getPose).
//
// Thread safety: none; one TagServo per control loop.
#pragma once

#include <memory>

#include "servo/unicycle.h"

namespace plslam {

struct TagServoOptions {
  double standoff = 0.5;           ///< desired distance from the camera to the tag along the optical axis, metres
  double gain_far = 0.5;           ///< vpServo gain for large errors, 1/s
  double gain_near = 2.0;          ///< vpServo gain at zero error, 1/s
  double gain_slope = 10.0;        ///< adaptive gain slope at zero error
  double depth_tolerance = 0.01;   ///< done within this depth error, metres
  double bearing_tolerance_deg = 1.0;  ///< and within this bearing of the tag centre, degrees
  UnicycleLimits limits;           ///< speed limits of the base
};

struct TagServoStep {
  VelocityCommand command;     ///< saturated; zero when done or the tag is not seen
  double depth_error = 0;      ///< Z - standoff, metres
  double bearing = 0;          ///< atan(x) of the tag centre, radians
  bool done = false;
};

class TagServo {
 public:
  /// bMc: the camera's pose in the base frame.
  TagServo(const vpHomogeneousMatrix& bMc, const TagServoOptions& options = {});
  ~TagServo();
  TagServo(const TagServo&) = delete;
  TagServo& operator=(const TagServo&) = delete;

  /// The command for the tag pose cMo in the camera frame.
  TagServoStep update(const vpHomogeneousMatrix& cMo);
  /// The command when the tag is not in view: stop.
  TagServoStep lost() const { return {}; }

 private:
  struct Task;
  TagServoOptions options_;
  std::unique_ptr<Task> task_;
};

}  // namespace plslam
