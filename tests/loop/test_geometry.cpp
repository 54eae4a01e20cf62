// Rigid 3D-3D registration: Umeyama on exact data, RANSAC with outliers.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/rigid_fit.h"
#include "loop/rigid_ransac.h"

using namespace plslam;

namespace {
SE3 someTransform() {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, -1, 0.2).normalized())),
             Eigen::Vector3d(0.5, -0.2, 0.3));
}

/// n random points in front of the camera (b) and the same points moved by T (a).
void exactPairs(const SE3& T, int n, std::mt19937* rng, std::vector<Eigen::Vector3d>* a, std::vector<Eigen::Vector3d>* b) {
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < n; ++i) {
    b->emplace_back(u(*rng), u(*rng), 2 + u(*rng));
    a->push_back(T * b->back());
  }
}
}  // namespace

TEST(RigidRansac, RecoversAnExactTransformFromInliersOnly) {
  std::mt19937 rng(1);
  const SE3 T = someTransform();
  std::vector<Eigen::Vector3d> a, b;
  exactPairs(T, 20, &rng, &a, &b);
  const RigidRansacResult r = ransacRigid(a, b, RigidRansacOptions{});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.inlier_count, 20);
  EXPECT_LT((r.T_a_b.translation() - T.translation()).norm(), 1e-9);
  EXPECT_LT(r.T_a_b.quaternion().angularDistance(T.quaternion()), 1e-9);
}

TEST(RigidRansac, FindsTheInliersAmongHalfOutliers) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, 0.005);
  const SE3 T = someTransform();
  std::vector<Eigen::Vector3d> a, b;
  std::vector<bool> truth;
  for (int i = 0; i < 200; ++i) {
    b.emplace_back(u(rng), u(rng), 2 + u(rng));
    const bool inlier = i % 2 == 0;
    a.push_back(inlier ? T * b.back() + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))
                       : Eigen::Vector3d(u(rng), u(rng), 2 + u(rng)));
    truth.push_back(inlier);
  }
  const RigidRansacResult r = ransacRigid(a, b, {});
  ASSERT_TRUE(r.ok);
  int agree = 0;
  for (size_t i = 0; i < truth.size(); ++i) agree += (r.inliers[i] != 0) == truth[i];
  EXPECT_GT(agree, 190);
  EXPECT_LT((r.T_a_b.translation() - T.translation()).norm(), 0.005);
  EXPECT_LT(r.T_a_b.quaternion().angularDistance(T.quaternion()), 0.005);
  // Too few points: no model.
  EXPECT_FALSE(ransacRigid({a[0], a[1]}, {b[0], b[1]}, {}).ok);
}

namespace {
/// Random segments in b and the same lines in a, with endpoints slid along the line (as a
/// second detection of the same edge would stop elsewhere).
std::vector<SegmentPair3D> segmentsUnder(const SE3& T, int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<SegmentPair3D> out;
  for (int i = 0; i < n; ++i) {
    SegmentPair3D s;
    const Eigen::Vector3d c(u(*rng), u(*rng), 2 + u(*rng)), d = Eigen::Vector3d(u(*rng), u(*rng), u(*rng)).normalized();
    s.p_b = c - 0.3 * d;
    s.q_b = c + 0.3 * d;
    s.p_a = T * (c + (0.1 + 0.2 * u(*rng)) * d);
    s.q_a = T * (c + (0.6 + 0.2 * u(*rng)) * d);
    out.push_back(s);
  }
  return out;
}
}  // namespace

TEST(RigidRansac, LinesJoinTheConsensusByTheirDistanceToTheLineNotTheirEndpoints) {
  std::mt19937 rng(3);
  const SE3 T = someTransform();
  std::vector<Eigen::Vector3d> a, b;
  exactPairs(T, 20, &rng, &a, &b);
  std::vector<SegmentPair3D> lines = segmentsUnder(T, 10, &rng);
  // Two wrong pairs: a's line moved off by 20 cm, and one turned by 30 degrees.
  lines[3].p_a += Eigen::Vector3d(0.2, 0, 0), lines[3].q_a += Eigen::Vector3d(0.2, 0, 0);
  lines[7].q_a = lines[7].p_a + Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) * (lines[7].q_a - lines[7].p_a);
  const RigidRansacResult r = ransacRigid(a, b, lines, {});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.inlier_count, 20);
  EXPECT_EQ(r.line_inlier_count, 8);
  EXPECT_FALSE(r.line_inliers[3]);
  EXPECT_FALSE(r.line_inliers[7]);
  EXPECT_LT((r.T_a_b.translation() - T.translation()).norm(), 1e-6);
}

TEST(RigidRansac, RefinementWithLinesFixesWhatThreePointsLeaveLoose) {
  // Three nearly collinear points fix the rotation about their line poorly; lines across
  // it pin it down.
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, 0.01);
  const SE3 T = someTransform();
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 3; ++i) {
    b.emplace_back(-0.5 + 0.5 * i, 0.02 * (i == 1), 2.0);
    a.push_back(T * b.back() + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  const std::vector<SegmentPair3D> lines = segmentsUnder(T, 12, &rng);
  const SE3 from_points = fitRigid(b, a)->T;
  const SE3 refined = refineRigid(from_points, a, b, {}, lines, {});
  const double before = from_points.quaternion().angularDistance(T.quaternion());
  const double after = refined.quaternion().angularDistance(T.quaternion());
  EXPECT_GT(before, 0.01);
  EXPECT_LT(after, 0.3 * before);
  // Without lines the refinement is the least-squares fit of the points.
  const SE3 points_only = refineRigid(from_points, a, b, {}, {}, {});
  EXPECT_LT((points_only.translation() - from_points.translation()).norm(), 1e-9);
}
