// The one least-squares rigid fit of plslam: the motion check's minimal samples and refits,
// loop verification's 3D-3D RANSAC and the trajectory alignment of the ATE all use it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "core/se3.h"

namespace plslam {

struct RigidFit {
  SE3 T;         ///< dst_i ~ T * src_i
  int rank = 0;  ///< of the pairs' cross-covariance: 2 or 3 fix T; 1 (collinear points) leaves a free rotation about their line, 0 (one place) any rotation; T is then one of the fits
  bool unique() const { return rank >= 2; }
};

/// Least-squares rigid transform with dst_i ~ T * src_i, each pair weighted (Horn/Umeyama
/// without scale; never a reflection). nullopt for fewer than 3 pairs, sizes that differ, or
/// weights that sum to no more than 0; a collinear set is a fit of rank 1, for the caller to
/// refuse (a pose from three points) or take (aligning a trajectory that went straight).
std::optional<RigidFit> fitRigid(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                                 const std::vector<double>& weights = {});

/// fitRigid's T when the pairs fix it (rank 2 or 3); nullopt otherwise (what a pose estimate
/// from point pairs needs: collinear points leave a free rotation).
std::optional<SE3> fitUniqueRigid(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                                  const std::vector<double>& weights = {});

/// fitUniqueRigid for exactly three pairs, in closed form and about five times faster (the
/// motion check fits thousands of minimal samples a frame). Three centred points span a plane,
/// so the least-squares rotation takes the source triangle's plane onto the destination's and
/// is a 2-D Procrustes rotation within it: the same optimum as the SVD, to rounding. nullopt
/// when either triangle is degenerate or the fit is not fixed (fitRigid's rank below 2).
std::optional<SE3> fitTriangleRigid(const std::array<Eigen::Vector3d, 3>& src,
                                    const std::array<Eigen::Vector3d, 3>& dst);

}  // namespace plslam
