// Synthetic point-line RGB-D scenes with exact ground truth for the optim tests and the
// optim benchmark: a few cameras on a smooth, curved path looking at a box of points and
// random 3D segments, exact ideal projections, then seeded noise.
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/se3.h"
#include "optim/bundle_adjuster.h"
#include "optim/pose_optimizer.h"

namespace plslam::test {

/// A 640x480 pinhole with TUM freiburg1 intrinsics and no distortion.
PinholeCamera syntheticCamera();

/// Pose of camera k of n on a curved path (an S in x-y with some z), looking at (0, 0, 3.5).
SE3 pathPose(int k, int n);

/// Rotation by `angle_deg` about a random axis and a translation of `trans_m` in a random
/// direction, applied on the right: T * delta.
SE3 perturb(const SE3& T, double trans_m, double angle_deg, std::mt19937& rng);

Eigen::Vector3d randomUnit(std::mt19937& rng);

/// Distance of X to the infinite line through P and Q.
double distanceToLine(const Eigen::Vector3d& X, const Eigen::Vector3d& P, const Eigen::Vector3d& Q);

struct Segment3 {
  Eigen::Vector3d P, Q;
};

/// World points seen by the camera at T_w_c: uniform pixels, depth uniform in [zmin, zmax].
std::vector<Eigen::Vector3d> pointsInView(const PinholeCamera& cam, const SE3& T_w_c, int n, double zmin,
                                          double zmax, std::mt19937& rng);
/// Random segments (random direction, 0.4-1.2 m long) whose endpoints are in view of every
/// camera given, with depth in [zmin, zmax] from the first; in every view the segment is at
/// least min_length_px long and at more than 30 degrees from the viewing ray, and (with
/// several cameras) the planes through the segment and the camera centres span more than
/// min_plane_angle_deg.
std::vector<Segment3> segmentsInView(const PinholeCamera& cam, const std::vector<SE3>& T_w_c, int n, double zmin,
                                     double zmax, std::mt19937& rng, double min_length_px = 60.0,
                                     double min_plane_angle_deg = 0.0);

/// The 2D segment a detector would report for S in camera T_w_c: projections of points a bit
/// inside/outside P and Q along the line (so endpoints do not correspond), plus pixel noise.
void observeSegment(const PinholeCamera& cam, const SE3& T_w_c, const Segment3& S, double noise_px,
                    std::mt19937& rng, Eigen::Vector2d* p, Eigen::Vector2d* q);

/// A pose-only problem at T_w_c: n_points points (with depth when with_depth) and n_lines
/// lines, pixel noise noise_px, depth noise from the default MeasurementModel times depth_noise_scale.
struct PoseOnlyScene {
  SE3 T_w_c_true;
  PoseOnlyProblem problem;
};
PoseOnlyScene makePoseOnlyScene(const PinholeCamera& cam, int n_points, int n_lines, bool with_depth,
                                double noise_px, double depth_noise_scale, std::mt19937& rng);

/// A bundle problem over n_kf keyframes of pathPose(): every point and line is in view of all
/// keyframes; a point is observed in all of them (views_per_point = 0) or in a window of
/// views_per_point consecutive ones; lines (1.2-2.5 m away) in all, and only lines whose
/// observation planes span more than min_line_plane_angle_deg (well triangulable: with 0.5 px
/// noise their endpoint Cramer-Rao std stays below about 3 mm). Initial values = truth
/// (callers perturb).
struct BundleScene {
  std::vector<SE3> T_w_c_true;
  std::vector<Eigen::Vector3d> points_true;
  std::vector<Segment3> lines_true;
  BundleProblem problem;
};
BundleScene makeBundleScene(const PinholeCamera& cam, int n_kf, int n_points, int n_lines, bool with_depth,
                            double noise_px, std::mt19937& rng, int views_per_point = 0,
                            double min_line_plane_angle_deg = 40.0);

}  // namespace plslam::test
