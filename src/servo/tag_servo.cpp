#include "servo/tag_servo.h"

#include <visp3/core/vpMath.h>
#include <visp3/core/vpVelocityTwistMatrix.h>
#include <visp3/visual_features/vpFeatureDepth.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpAdaptiveGain.h>
#include <visp3/vs/vpServo.h>

#include <cmath>

#include "core/error.h"

namespace plslam {

struct TagServo::Task {
  vpServo servo;
  vpFeaturePoint x, x_star;
  vpFeatureDepth z, z_star;
};

TagServo::TagServo(const vpHomogeneousMatrix& bMc, const TagServoOptions& options)
    : options_(options), task_(std::make_unique<Task>()) {
  if (!(options.standoff > 0)) throw ConfigError("tag servo: the standoff must be positive");
  vpServo& s = task_->servo;
  s.setServo(vpServo::EYEINHAND_L_cVe_eJe);
  s.setInteractionMatrixType(vpServo::CURRENT, vpServo::PSEUDO_INVERSE);
  s.set_cVe(vpVelocityTwistMatrix(bMc.inverse()));  // cMe, e = the base
  s.set_eJe(unicycleJacobian());
  s.setLambda(vpAdaptiveGain(options.gain_near, options.gain_far, options.gain_slope));
  task_->x_star.buildFrom(0, 0, options.standoff);
  task_->z_star.buildFrom(0, 0, options.standoff, 0);  // log(Z*/Z*) = 0
  s.addFeature(task_->x, task_->x_star, vpFeaturePoint::selectX());
  s.addFeature(task_->z, task_->z_star);
}

TagServo::~TagServo() = default;

TagServoStep TagServo::update(const vpHomogeneousMatrix& cMo) {
  const double X = cMo[0][3], Y = cMo[1][3], Z = cMo[2][3];
  TagServoStep step;
  if (!(Z > 0)) return step;  // behind the camera: not a usable detection
  const double x = X / Z, y = Y / Z;
  step.depth_error = Z - options_.standoff;
  step.bearing = std::atan(x);
  task_->x.buildFrom(x, y, Z);
  task_->z.buildFrom(x, y, Z, std::log(Z / options_.standoff));
  const vpColVector q = task_->servo.computeControlLaw();
  if (std::abs(step.depth_error) <= options_.depth_tolerance &&
      std::abs(step.bearing) <= vpMath::rad(options_.bearing_tolerance_deg)) {
    step.done = true;
    return step;
  }
  step.command = saturate({q[0], q[1]}, options_.limits);
  return step;
}

}  // namespace plslam
