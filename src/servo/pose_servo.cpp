#include "servo/pose_servo.h"

#include <visp3/core/vpMath.h>
#include <visp3/core/vpRotationMatrix.h>
#include <visp3/core/vpVelocityTwistMatrix.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/visual_features/vpFeatureThetaU.h>
#include <visp3/visual_features/vpGenericFeature.h>
#include <visp3/vs/vpAdaptiveGain.h>
#include <visp3/vs/vpServo.h>

#include <cmath>

namespace plslam {

const char* toString(ServoStage stage) {
  switch (stage) {
    case ServoStage::kTurn: return "turn";
    case ServoStage::kApproach: return "approach";
    case ServoStage::kAlign: return "align";
    case ServoStage::kDone: return "done";
  }
  return "?";
}

namespace {

// The virtual camera of the approach: at the base, z along the base x axis (vpPioneer's
// mounting without its offset): cMe with x_c = -y_e, y_c = -z_e, z_c = x_e.
vpHomogeneousMatrix forwardCameraInBase() {
  vpRotationMatrix eRc;
  eRc[0][0] = 0, eRc[0][1] = 0, eRc[0][2] = 1;
  eRc[1][0] = -1, eRc[1][1] = 0, eRc[1][2] = 0;
  eRc[2][0] = 0, eRc[2][1] = -1, eRc[2][2] = 0;
  return vpHomogeneousMatrix(vpTranslationVector(0, 0, 0), eRc);  // eMc
}

}  // namespace

struct PoseServo::Tasks {
  // Turn / align: theta-u about z of c*Rc (the base frame is the "camera", cVe = I).
  vpServo turn;
  vpFeatureThetaU tu{vpFeatureThetaU::cdRc};
  // Approach: image abscissa and depth of the goal point in the forward virtual camera.
  vpServo approach;
  vpFeaturePoint x, x_star;
  vpGenericFeature z{1}, z_star{1};
  vpHomogeneousMatrix cMe;

  explicit Tasks(const PoseServoOptions& o) {
    vpMatrix eJw(6, 1, 0.0);
    eJw[5][0] = 1;  // only w moves the base in the turn stages
    turn.setServo(vpServo::EYEINHAND_L_cVe_eJe);
    turn.setInteractionMatrixType(vpServo::CURRENT, vpServo::PSEUDO_INVERSE);
    turn.set_cVe(vpVelocityTwistMatrix());
    turn.set_eJe(eJw);
    turn.setLambda(o.turn_gain);
    turn.addFeature(tu, vpFeatureThetaU::selectTUz());

    cMe = forwardCameraInBase().inverse();
    approach.setServo(vpServo::EYEINHAND_L_cVe_eJe);
    approach.setInteractionMatrixType(vpServo::CURRENT, vpServo::PSEUDO_INVERSE);
    approach.set_cVe(vpVelocityTwistMatrix(cMe));
    approach.set_eJe(unicycleJacobian());
    approach.setLambda(vpAdaptiveGain(o.gain_near, o.gain_far, o.gain_slope));
    x_star.buildFrom(0, 0, 1);
    z_star.set_s(0.0);
    approach.addFeature(x, x_star, vpFeaturePoint::selectX());
    approach.addFeature(z, z_star);
  }

  /// w that turns the base from `yaw` to `target_yaw`.
  double turnTowards(double yaw, double target_yaw) {
    tu.buildFrom(vpRotationMatrix(0, 0, wrapAngle(yaw - target_yaw)));  // c*Rc
    return turn.computeControlLaw()[0];
  }

  /// (v, w) that drive the base at pMb to the goal point (gx, gy).
  VelocityCommand towards(const vpHomogeneousMatrix& pMb, double gx, double gy) {
    const vpColVector g_p(std::vector<double>{gx, gy, 0.0, 1.0});
    const vpColVector g_c = cMe * pMb.inverse() * g_p;
    const double X = g_c[0], Y = g_c[1], Z = g_c[2];
    x.buildFrom(X / Z, Y / Z, Z);
    z.set_s(Z);
    // dZ/dt for a static point seen by a camera moving with (v, omega): -v_z - y Z w_x + x Z w_y.
    vpMatrix Lz(1, 6, 0.0);
    Lz[0][2] = -1;
    Lz[0][3] = -(Y / Z) * Z;
    Lz[0][4] = (X / Z) * Z;
    z.setInteractionMatrix(Lz);
    const vpColVector q = approach.computeControlLaw();
    return {q[0], q[1]};
  }
};

PoseServo::PoseServo(const PlanarPose& goal, const PoseServoOptions& options)
    : goal_(goal), options_(options), tasks_(std::make_unique<Tasks>(options)) {}

PoseServo::~PoseServo() = default;

ServoStep PoseServo::update(const vpHomogeneousMatrix& pMb) {
  const PlanarPose now = PlanarMap::planar(pMb);
  const double dx = goal_.x - now.x, dy = goal_.y - now.y;
  const double rho = std::hypot(dx, dy);
  const double bearing = wrapAngle(std::atan2(dy, dx) - now.yaw);
  const double yaw_error = wrapAngle(now.yaw - goal_.yaw);
  const double tol = options_.position_tolerance;
  const double yaw_tol = vpMath::rad(options_.yaw_tolerance_deg);

  // Stage transitions (with hysteresis, so noise does not make the stages chatter).
  if (stage_ == ServoStage::kAlign || stage_ == ServoStage::kDone) {
    if (rho > options_.reapproach_factor * tol) stage_ = ServoStage::kTurn;
  }
  if (stage_ == ServoStage::kTurn || stage_ == ServoStage::kApproach) {
    if (rho <= tol) {
      stage_ = ServoStage::kAlign;
    } else if (stage_ == ServoStage::kTurn && std::abs(bearing) <= vpMath::rad(options_.turn_done_deg)) {
      stage_ = ServoStage::kApproach;
    } else if (stage_ == ServoStage::kApproach && std::abs(bearing) > vpMath::rad(options_.turn_first_deg)) {
      stage_ = ServoStage::kTurn;
    }
  }
  if (stage_ == ServoStage::kAlign && std::abs(yaw_error) <= yaw_tol) stage_ = ServoStage::kDone;
  if (stage_ == ServoStage::kDone && std::abs(yaw_error) > 2 * yaw_tol) stage_ = ServoStage::kAlign;

  ServoStep step;
  step.stage = stage_;
  step.position_error = rho;
  step.yaw_error = yaw_error;
  VelocityCommand command;
  switch (stage_) {
    case ServoStage::kTurn: command.w = tasks_->turnTowards(now.yaw, now.yaw + bearing); break;
    case ServoStage::kApproach: command = tasks_->towards(pMb, goal_.x, goal_.y); break;
    case ServoStage::kAlign: command.w = tasks_->turnTowards(now.yaw, goal_.yaw); break;
    case ServoStage::kDone: step.done = true; break;
  }
  step.command = saturate(command, options_.limits);
  return step;
}

}  // namespace plslam
