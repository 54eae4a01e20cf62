#include "optim/measurement.h"

#include <Eigen/Geometry>
#include <cmath>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

double MeasurementModel::pixelSigma(int octave) const {
  return pixel_sigma * std::pow(scale_factor, static_cast<double>(octave));
}

bool MeasurementModel::hasDepth(double depth) const {
  return use_depth && std::isfinite(depth) && depth > min_depth;
}

void MeasurementModel::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw ConfigError(str("optim: ", name, " must be > 0 (got ", v, ")"));
  };
  positive(pixel_sigma, "pixel_sigma");
  positive(depth_sigma_coeff, "depth_sigma_coeff");
  positive(chi2_2dof, "chi2_2dof");
  positive(chi2_3dof, "chi2_3dof");
  positive(min_depth, "min_depth");
  if (!(scale_factor >= 1.0) || !std::isfinite(scale_factor))
    throw ConfigError(str("optim: scale_factor must be >= 1 (got ", scale_factor, ")"));
}

const char* toString(OptimStatus status) {
  switch (status) {
    case OptimStatus::kOk: return "ok";
    case OptimStatus::kNoObservations: return "no observations";
    case OptimStatus::kNoValidObservations: return "no valid observations (all behind the camera or degenerate)";
    case OptimStatus::kTooFewInliers: return "too few inliers";
    case OptimStatus::kSolverFailed: return "solver failed";
    case OptimStatus::kNothingToOptimise: return "nothing to optimise (all parameters fixed)";
  }
  return "unknown";
}

bool normalisedLine(const Eigen::Vector2d& p, const Eigen::Vector2d& q, Eigen::Vector3d* l) {
  const Eigen::Vector3d h = Eigen::Vector3d(p.x(), p.y(), 1.0).cross(Eigen::Vector3d(q.x(), q.y(), 1.0));
  const double n = std::hypot(h.x(), h.y());  // == |q - p|
  if (!(n > 1e-6) || !std::isfinite(n)) return false;
  *l = h / n;
  return true;
}

}  // namespace plslam
