#include "synth/fast_motion.h"

#include <algorithm>
#include <cmath>

#include "synth/hash.h"

namespace plslam::synth {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kTwoPi = 2.0 * M_PI;

/// The bursts of one cycle but the last (which returns to the start). Chosen so that the
/// camera keeps looking at the shelf, table, cabinet or pictures from 2.3 to 4.8 m, with
/// translation peaks of 0.7 to 1 m/s at the default 180 deg/s.
const FastBurst kBursts[] = {
    // yaw pitch roll (deg), dx dy dz (m), rate fraction, calm (s)
    {40, 4, 0, -0.15, 0.05, 0.0, 1.0, 0.7},     // pan left to the shelf
    {-75, -6, 10, 0.35, 0.10, -0.08, 0.9, 0.6},  // swing right to the cabinet, stepping right
    {8, 0, -25, 0.0, 0.15, 0.05, 0.8, 0.5},      // a wrist roll
    {45, 10, 18, -0.25, -0.10, 0.10, 1.0, 0.8},  // back to the north wall, rolling
    {-30, -14, -5, 0.10, -0.12, -0.12, 0.75, 0.6},
    {35, 8, -10, -0.15, 0.05, 0.05, 0.95, 0.6},
};

/// Raised-cosine step: 0 at u = 0, 1 at u = 1, zero first and second derivatives at both ends.
double burstProgress(double u) { return u - std::sin(kTwoPi * u) / kTwoPi; }

/// 0 below 0, 1 above 1, C2 in between (Perlin's smootherstep).
double smootherstep(double u) {
  if (u <= 0) return 0;
  if (u >= 1) return 1;
  return u * u * u * (u * (6 * u - 15) + 10);
}

}  // namespace

SE3 lookPose(const Eigen::Vector3d& p, double yaw, double pitch, double roll) {
  const Eigen::Vector3d f(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const Eigen::Vector3d r = f.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d d = f.cross(r);
  Eigen::Matrix3d R;
  R.col(0) = std::cos(roll) * r + std::sin(roll) * d;
  R.col(1) = -std::sin(roll) * r + std::cos(roll) * d;
  R.col(2) = f;
  return SE3(R, p);
}

FastPath::FastPath(double max_rotation_deg_s) {
  bursts_.assign(std::begin(kBursts), std::end(kBursts));
  FastBurst back{0, 0, 0, 0, 0, 0, 0.85, 0.7};
  for (const FastBurst& b : bursts_) {
    back.yaw_deg -= b.yaw_deg, back.pitch_deg -= b.pitch_deg, back.roll_deg -= b.roll_deg;
    back.dx -= b.dx, back.dy -= b.dy, back.dz -= b.dz;
  }
  bursts_.push_back(back);
  double t = kFastFirstBurstS;
  for (const FastBurst& b : bursts_) {
    // A raised-cosine profile peaks at twice the mean rate.
    const double angle = std::sqrt(b.yaw_deg * b.yaw_deg + b.pitch_deg * b.pitch_deg + b.roll_deg * b.roll_deg);
    const double duration = 2.0 * angle / (b.rate_fraction * max_rotation_deg_s);
    starts_.push_back(t);
    durations_.push_back(duration);
    t += duration + b.calm_s;
  }
  cycle_s_ = t - kFastFirstBurstS;
}

SE3 FastPath::poseAt(double t) const {
  // The bursts done so far (whole cycles add nothing), plus the part of the current one.
  double yaw = 0, pitch = 0, roll = 0;
  Eigen::Vector3d dp(0, 0, 0);
  if (t > kFastFirstBurstS) {
    const double u = kFastFirstBurstS + std::fmod(t - kFastFirstBurstS, cycle_s_);
    for (size_t k = 0; k < bursts_.size() && u > starts_[k]; ++k) {
      const double w = burstProgress(std::min(1.0, (u - starts_[k]) / durations_[k]));
      const FastBurst& b = bursts_[k];
      yaw += w * b.yaw_deg, pitch += w * b.pitch_deg, roll += w * b.roll_deg;
      dp += w * Eigen::Vector3d(b.dx, b.dy, b.dz);
    }
  }
  // A slow hand-held drift all along (a few deg/s, under 0.1 m/s).
  auto wave = [t](double period, double phase) { return std::sin(kTwoPi * t / period + phase); };
  const Eigen::Vector3d p = Eigen::Vector3d(0.06 * wave(6, 0.3), -1.2 + 0.05 * wave(5, 1.1), 1.45 + 0.03 * wave(4, 0.5)) + dp;
  return lookPose(p, (75 + 4 * wave(7, 0.4) + yaw) * kDeg, (-12 + 3 * wave(6, 1.3) + pitch) * kDeg,
                  (2 * wave(5, 0) + roll) * kDeg);
}

ExposureGain::ExposureGain(uint64_t seed, double duration_s) : varying_(true) {
  const uint64_t base = hash2(seed, 0x9a1);
  phase0_ = kTwoPi * unitFromHash(hash2(base, 0));
  phase1_ = kTwoPi * unitFromHash(hash2(base, 1));
  // Auto-exposure re-adjustments every 1.2 to 2.5 s, alternately brighter and darker.
  double t = 1.0;
  for (uint64_t k = 0; t < duration_s; ++k) {
    step_times_.push_back(t);
    levels_.push_back((k % 2 ? -1.0 : 1.0) * (0.08 + 0.12 * unitFromHash(hash3(base, 2, k))));
    t += 1.2 + 1.3 * unitFromHash(hash3(base, 3, k));
  }
}

double ExposureGain::at(double t) const {
  if (!varying_) return 1.0;
  double level = 0;
  for (size_t k = 0; k < step_times_.size() && t > step_times_[k]; ++k)
    level += (levels_[k] - level) * smootherstep((t - step_times_[k]) / 0.2);
  return 1.0 + 0.12 * std::sin(kTwoPi * t / 6.3 + phase0_) + 0.06 * std::sin(kTwoPi * t / 2.3 + phase1_) + level;
}

}  // namespace plslam::synth
