// Rigid 3D-3D registration of points and line segments: Horn/Umeyama closed form (no
// scale) inside RANSAC on minimal samples of three point correspondences; the consensus
// counts points and lines; then least-squares refinement on the inliers of both until the
// inlier sets settle. The inlier gate grows with depth like the sensor noise:
// |p_a - T_a_b p_b| < threshold_m + depth_coeff * z^2 (z: depth of p_a).
// A segment's endpoints are where its detection happened to stop, so a line pair is
// compared by the distance of b's endpoints (moved by T_a_b) to a's infinite line, each
// under the same gate, and by the angle between the two directions.
//
// Deterministic for a given seed. Stateless; thread-safe.
#pragma once

#include <string>
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/se3.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindRigidRansacOptions (loop/option_keys.cpp). `plslam run --print-config` lists them.
struct RigidRansacOptions {
  int iterations = 300;
  double threshold_m = 0.03;
  double depth_coeff = 0.01;
  int refine_rounds = 5;
  double line_angle_deg = 5;
  uint64_t seed = 1;
};

/// Binds `prefix` + "iterations", "threshold_m", ...
void bindRigidRansacOptions(OptionTable* table, const std::string& prefix, RigidRansacOptions* options);

/// A pair of matched 3D segments (endpoints in each camera frame).
struct SegmentPair3D {
  Eigen::Vector3d p_a, q_a;  ///< segment in a (defines the line)
  Eigen::Vector3d p_b, q_b;  ///< segment in b
};

struct RigidRansacResult {
  bool ok = false;               ///< a model with at least three point inliers was found
  SE3 T_a_b;                     ///< maps points of b onto points of a
  std::vector<char> inliers;     ///< per point correspondence
  int inlier_count = 0;          ///< point inliers
  std::vector<char> line_inliers;  ///< per segment pair
  int line_inlier_count = 0;
  double rmse_m = 0;             ///< over the point inliers
};

/// Whether a segment pair agrees with `T_a_b` (the line gate above).
bool segmentsAgree(const SegmentPair3D& pair, const SE3& T_a_b, const RigidRansacOptions& options);

/// Refines `T_a_b` by Gauss-Newton on the selected point pairs (3D distance) and segment
/// pairs (distance of b's endpoints to a's line). Empty selections select all.
SE3 refineRigid(const SE3& T_a_b, const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                const std::vector<char>& point_select, const std::vector<SegmentPair3D>& lines,
                const std::vector<char>& line_select, int iterations = 5);

RigidRansacResult ransacRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                              const RigidRansacOptions& options);
/// The same with segment pairs in the consensus and in the refinement.
RigidRansacResult ransacRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                              const std::vector<SegmentPair3D>& lines, const RigidRansacOptions& options);

}  // namespace plslam
