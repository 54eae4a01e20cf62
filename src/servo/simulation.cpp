#include "servo/simulation.h"

#include <visp3/core/vpThetaUVector.h>
#include <visp3/robot/vpSimulatorPioneer.h>

#include <algorithm>
#include <cmath>

#include "camera/visp_conversion.h"
#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {

// vpSimulatorPioneer starts at the origin; its state is protected, so a subclass places it.
class SimulatedBase : public vpSimulatorPioneer {
 public:
  SimulatedBase(const SimulationOptions& o, const UnicycleLimits& limits) {
    cMe_ = o.bMc.inverse();  // vpPioneer hides vpUnicycle::set_cMe(cMe)
    setSamplingTime(o.dt);
    setMaxTranslationVelocity(limits.v_max);
    setMaxRotationVelocity(limits.w_max);
    xm_ = o.start.x;
    ym_ = o.start.y;
    theta_ = o.start.yaw;
    wMe_ = PlanarMap::toMatrix(o.start);
    wMc_ = wMe_ * cMe_.inverse();
  }
  PlanarPose pose() const { return {xm_, ym_, wrapAngle(theta_)}; }
  vpHomogeneousMatrix camera() const { return wMc_; }
  void apply(const VelocityCommand& c) {
    vpColVector q(2);
    q[0] = c.v;
    q[1] = c.w;
    setVelocity(vpRobot::ARTICULAR_FRAME, q);
  }
};

void track(SimulationResult* r, const VelocityCommand& c) {
  r->max_abs_v = std::max(r->max_abs_v, std::abs(c.v));
  r->max_abs_w = std::max(r->max_abs_w, std::abs(c.w));
  r->commands.push_back(c);
}

}  // namespace

SlamPoseError::SlamPoseError(std::vector<SE3> errors) : errors_(std::move(errors)) {
  if (errors_.empty()) errors_.push_back(SE3());
}

std::optional<vpHomogeneousMatrix> SlamPoseError::measure(int step, const vpHomogeneousMatrix& wMc_true) {
  // Back and forth through the run (0 1 .. n-1 n-2 .. 1 0 1 ..): the error stays as smooth as
  // SLAM's, with no jump from the last frame back to the first.
  const size_t n = errors_.size();
  size_t k = n > 1 ? static_cast<size_t>(step) % (2 * n - 2) : 0;
  if (k >= n) k = 2 * n - 2 - k;
  return wMc_true * toVisp(errors_[k]);
}

std::vector<SE3> SlamPoseError::cameraErrors(const Trajectory& estimate, const Trajectory& groundtruth, double max_dt_s) {
  const TimeNs max_dt = secondsToNs(max_dt_s);
  std::vector<std::pair<SE3, SE3>> pairs;  // (gt, est)
  for (const StampedPose& e : estimate) {
    auto it = std::lower_bound(groundtruth.begin(), groundtruth.end(), e.t_ns,
                               [](const StampedPose& g, TimeNs t) { return g.t_ns < t; });
    const StampedPose* best = nullptr;
    if (it != groundtruth.end()) best = &*it;
    if (it != groundtruth.begin() && (!best || e.t_ns - std::prev(it)->t_ns < best->t_ns - e.t_ns)) best = &*std::prev(it);
    if (best && std::llabs(best->t_ns - e.t_ns) <= max_dt) pairs.emplace_back(best->T_w_c, e.T_w_c);
  }
  if (pairs.size() < 2) throw DataError(str("SLAM pose errors: only ", pairs.size(), " of ", estimate.size(),
                                            " estimated poses have a ground truth pose within ", max_dt_s, " s"));
  const SE3 T_align = pairs.front().first * pairs.front().second.inverse();
  std::vector<SE3> errors;
  errors.reserve(pairs.size());
  for (const auto& [gt, est] : pairs) errors.push_back(gt.inverse() * (T_align * est));
  return errors;
}

void SlamPoseError::magnitude(const std::vector<SE3>& errors, double* max_translation, double* max_rotation) {
  *max_translation = 0;
  *max_rotation = 0;
  for (const SE3& e : errors) {
    *max_translation = std::max(*max_translation, e.translation().norm());
    *max_rotation = std::max(*max_rotation, Eigen::AngleAxisd(e.rotation()).angle());
  }
}

GaussianPoseError::GaussianPoseError(double sigma_position_m, double sigma_rotation_rad, unsigned seed)
    : sigma_p_(sigma_position_m), sigma_r_(sigma_rotation_rad), rng_(seed) {}

std::optional<vpHomogeneousMatrix> GaussianPoseError::measure(int, const vpHomogeneousMatrix& wMc_true) {
  std::normal_distribution<double> p(0, sigma_p_ > 0 ? sigma_p_ : 1e-300), r(0, sigma_r_ > 0 ? sigma_r_ : 1e-300);
  const vpTranslationVector t(p(rng_), p(rng_), p(rng_));
  const vpThetaUVector tu(r(rng_), r(rng_), r(rng_));
  return wMc_true * vpHomogeneousMatrix(t, tu);
}

SimulationResult simulatePoseServo(const PlanarPose& goal, const PoseServoOptions& servo, const SimulationOptions& sim,
                                   PoseErrorModel* errors, VelocitySink* sink) {
  SimulatedBase base(sim, servo.limits);
  PoseServo controller(goal, servo);
  // The SLAM map is the first camera frame; the plane frame is the simulator's world.
  const vpHomogeneousMatrix pMw = base.camera();
  const PlanarMap map(sim.bMc, pMw);
  SimulationResult r;
  const int max_steps = static_cast<int>(std::ceil(sim.max_time_s / sim.dt));
  for (int k = 0; k < max_steps; ++k) {
    const vpHomogeneousMatrix wMc_true = pMw.inverse() * base.camera();
    const std::optional<vpHomogeneousMatrix> wMc = errors ? errors->measure(k, wMc_true) : wMc_true;
    r.iterations = k + 1;
    if (!wMc) ++r.blind_steps;
    const ServoStep step = wMc ? controller.update(map.baseInPlane(*wMc)) : ServoStep{};  // no pose: stop
    if (sink) sink->send(secondsToNs(k * sim.dt), step.command);
    track(&r, step.command);
    if (step.done) {
      r.converged = true;
      break;
    }
    base.apply(step.command);
  }
  r.sim_time_s = r.iterations * sim.dt;
  r.final_pose = base.pose();
  r.position_error = std::hypot(r.final_pose.x - goal.x, r.final_pose.y - goal.y);
  r.yaw_error = wrapAngle(r.final_pose.yaw - goal.yaw);
  return r;
}

SimulationResult simulateTagServo(const vpHomogeneousMatrix& pMo, const TagServoOptions& servo,
                                  const SimulationOptions& sim, VelocitySink* sink, TagSensor* sensor) {
  SimulatedBase base(sim, servo.limits);
  TagServo controller(sim.bMc, servo);
  SimulationResult r;
  const int max_steps = static_cast<int>(std::ceil(sim.max_time_s / sim.dt));
  TagServoStep step;
  for (int k = 0; k < max_steps; ++k) {
    const std::optional<vpHomogeneousMatrix> cMo =
        sensor ? sensor->observe(k, base.camera()) : std::optional(base.camera().inverse() * pMo);
    r.iterations = k + 1;
    if (!cMo) ++r.blind_steps;
    step = cMo ? controller.update(*cMo) : controller.lost();
    if (sink) sink->send(secondsToNs(k * sim.dt), step.command);
    track(&r, step.command);
    if (step.done) {
      r.converged = true;
      break;
    }
    base.apply(step.command);
  }
  r.sim_time_s = r.iterations * sim.dt;
  r.final_pose = base.pose();
  const vpHomogeneousMatrix cMo = base.camera().inverse() * pMo;
  r.position_error = cMo[2][3] - servo.standoff;
  r.yaw_error = std::atan2(cMo[0][3], cMo[2][3]);
  return r;
}

}  // namespace plslam
