// Rigid 3D-3D registration: Horn/Umeyama closed form (no scale) inside RANSAC on minimal
// samples of three correspondences, then least-squares refinement on the inliers until the
// inlier set settles. The inlier gate grows with depth like the sensor noise:
// |p_a - T_a_b p_b| < threshold_m + depth_coeff * z^2 (z: depth of p_a).
//
// Deterministic for a given seed. Stateless; thread-safe.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/se3.h"

namespace plslam {

struct RigidRansacOptions {
  int iterations = 300;         ///< RANSAC samples
  double threshold_m = 0.03;    ///< inlier distance at zero depth, metres
  double depth_coeff = 0.01;    ///< plus this times depth squared (1/m)
  int refine_rounds = 5;        ///< least-squares refits on the inliers
  uint64_t seed = 1;            ///< sampling seed
};

struct RigidRansacResult {
  bool ok = false;               ///< a model with at least three inliers was found
  SE3 T_a_b;                     ///< maps points of b onto points of a
  std::vector<char> inliers;     ///< per correspondence
  int inlier_count = 0;
  double rmse_m = 0;             ///< over the inliers
};

/// Least-squares rigid transform with p_a ~ T * p_b over the selected correspondences
/// (all when `select` is empty). Needs three non-collinear points; returns identity otherwise.
SE3 umeyamaRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                 const std::vector<char>& select = {});

RigidRansacResult ransacRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                              const RigidRansacOptions& options);

}  // namespace plslam
