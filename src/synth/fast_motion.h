// The camera path and the camera effects of the `fast` synthetic scene: a hand-held camera
// with bursts of fast rotation and translation, and an exposure gain that drifts and steps
// like an auto-exposure. Both are smooth functions of time, so ground-truth velocities are
// exact; the renderer (synth/renderer.h) turns the path into motion blur and applies the gain.
#pragma once

#include <cstdint>
#include <vector>

#include "core/se3.h"

namespace plslam::synth {

/// T_w_c of a camera at `p` looking along yaw (from +x towards +y, radians), pitch (up
/// positive), rolled about its optical axis; camera x right, y down, z forward. The paths
/// of every scene kind are made with it.
SE3 lookPose(const Eigen::Vector3d& p, double yaw, double pitch, double roll);

/// One burst of the fast path: a change of the look angles (degrees) and of the position
/// (metres) with a raised-cosine velocity profile (zero velocity and acceleration at both
/// ends), then a calm stretch with only the slow hand-held drift.
struct FastBurst {
  double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
  double dx = 0, dy = 0, dz = 0;
  double rate_fraction = 1.0;  ///< peak rotation rate as a fraction of the path's maximum
  double calm_s = 0.5;         ///< calm stretch after the burst, seconds
};

/// The fast scene's camera path: slow drift for the first `kFastFirstBurstS` seconds
/// (initialisation), then the bursts in order, repeated (their changes sum to zero, so the
/// path is periodic after the first burst and stays in front of the furniture).
class FastPath {
 public:
  /// Burst durations are chosen so that each burst's peak rotation rate is
  /// rate_fraction * max_rotation_deg_s.
  explicit FastPath(double max_rotation_deg_s);
  /// T_w_c at t seconds after frame 0.
  SE3 poseAt(double t_s) const;
  /// Start and duration of every burst of the first cycle, seconds.
  const std::vector<double>& burstStarts() const { return starts_; }
  const std::vector<double>& burstDurations() const { return durations_; }
  double cycleSeconds() const { return cycle_s_; }

 private:
  std::vector<FastBurst> bursts_;
  std::vector<double> starts_, durations_;
  double cycle_s_ = 0;
};

/// Start of the first burst, seconds after frame 0 (before it the camera moves slowly).
constexpr double kFastFirstBurstS = 1.2;

/// The exposure gain of the fast scene: 1 plus two slow waves (phases from the seed) plus
/// auto-exposure-like levels that step (over 0.2 s) at seeded times from 1 s on.
/// Stays within [0.62, 1.38].
class ExposureGain {
 public:
  ExposureGain() = default;  ///< a constant gain of 1
  ExposureGain(uint64_t seed, double duration_s);
  double at(double t_s) const;

 private:
  bool varying_ = false;
  double phase0_ = 0, phase1_ = 0;
  std::vector<double> step_times_, levels_;  // levels_[k] holds from step_times_[k] on
};

}  // namespace plslam::synth
