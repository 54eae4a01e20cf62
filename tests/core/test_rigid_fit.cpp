#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/rigid_fit.h"

using namespace plslam;

namespace {
const SE3 kT(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized())), Eigen::Vector3d(0.3, -1, 2));

std::vector<Eigen::Vector3d> moved(const std::vector<Eigen::Vector3d>& points, const SE3& T) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : points) out.push_back(T * p);
  return out;
}
}  // namespace

TEST(RigidFit, RecoversAKnownTransformFromThreeOrMorePoints) {
  const std::vector<Eigen::Vector3d> a = {{0, 0, 1}, {1, 0, 2}, {0, 1, 3}, {1, 1, 1}};
  const auto fit = fitRigid(a, moved(a, kT));
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->rank, 3);
  EXPECT_TRUE(fit->unique());
  EXPECT_LT((fit->T.matrix() - kT.matrix()).norm(), 1e-9);
}

TEST(RigidFit, PointsOnAPlaneGiveTheProperRotationNotItsMirrorImage) {
  std::vector<Eigen::Vector3d> a;
  for (int k = 0; k < 20; ++k) a.emplace_back(std::cos(0.3 * k), std::sin(0.3 * k), 0.0);
  const auto fit = fitRigid(a, moved(a, kT));
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->rank, 2);
  EXPECT_TRUE(fit->unique());
  EXPECT_NEAR(fit->T.rotation().determinant(), 1.0, 1e-12);
  EXPECT_LT((fit->T.inverse() * kT).angle(), 1e-7);
}

TEST(RigidFit, CollinearPointsFitButAreNotUnique) {
  // A trajectory that went straight: any rotation about the line fits, and one is returned.
  const std::vector<Eigen::Vector3d> a = {{0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0, 0, 5}};
  const std::vector<Eigen::Vector3d> b = moved(a, kT);
  const auto fit = fitRigid(a, b);
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->rank, 1);
  EXPECT_FALSE(fit->unique());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_LT((fit->T * a[i] - b[i]).norm(), 1e-9);
}

TEST(RigidFit, WeightsDecideBetweenDisagreeingPairs) {
  // Four pairs moved by kT and one moved 1 m further: weight 0 on it gives kT exactly.
  std::vector<Eigen::Vector3d> a = {{0, 0, 1}, {1, 0, 2}, {0, 1, 3}, {1, 1, 1}, {2, 1, 1}};
  std::vector<Eigen::Vector3d> b = moved(a, kT);
  b[4] += Eigen::Vector3d(1, 0, 0);
  const auto weighted = fitRigid(a, b, {1, 1, 1, 1, 0});
  const auto plain = fitRigid(a, b);
  ASSERT_TRUE(weighted && plain);
  EXPECT_LT((weighted->T.matrix() - kT.matrix()).norm(), 1e-9);
  EXPECT_GT((plain->T.matrix() - kT.matrix()).norm(), 1e-3);
}

TEST(RigidFit, TooFewPairsOrNoWeightGiveNoFit) {
  const std::vector<Eigen::Vector3d> a = {{0, 0, 1}, {1, 0, 2}, {0, 1, 3}};
  EXPECT_FALSE(fitRigid({a[0], a[1]}, {a[0], a[1]}).has_value());
  EXPECT_FALSE(fitRigid(a, {a[0], a[1]}).has_value());
  EXPECT_FALSE(fitRigid(a, a, {0, 0, 0}).has_value());
  EXPECT_FALSE(fitRigid(a, a, {1, 1}).has_value());
}

TEST(RigidFit, ATrianglesClosedFormFitIsTheSvdsFit) {
  // Noisy pairs, and pairs with one point thrown elsewhere (the best fit is then far from any
  // rigid motion).
  std::mt19937_64 rng(7);
  std::normal_distribution<double> unit(0, 1);
  const auto random_point = [&] { return Eigen::Vector3d(unit(rng), unit(rng), 3 + unit(rng)); };
  for (int trial = 0; trial < 2000; ++trial) {
    std::array<Eigen::Vector3d, 3> a, b;
    for (int i = 0; i < 3; ++i) {
      a[i] = random_point();
      b[i] = kT * a[i] + 0.01 * (random_point() - Eigen::Vector3d(0, 0, 3));
    }
    if (trial % 3 == 0) b[trial % 2] = random_point();
    const auto svd = fitUniqueRigid({a.begin(), a.end()}, {b.begin(), b.end()});
    const auto closed = fitTriangleRigid(a, b);
    ASSERT_EQ(svd.has_value(), closed.has_value()) << "trial " << trial;
    if (!svd) continue;
    EXPECT_LT((svd->matrix() - closed->matrix()).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    EXPECT_NEAR(closed->rotation().determinant(), 1.0, 1e-12);
  }
}

TEST(RigidFit, ATriangleFitRecoversAMotionAndRefusesADegenerateTriangle) {
  const std::array<Eigen::Vector3d, 3> a = {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 2),
                                            Eigen::Vector3d(0, 1, 3)};
  const std::array<Eigen::Vector3d, 3> b = {kT * a[0], kT * a[1], kT * a[2]};
  const auto fit = fitTriangleRigid(a, b);
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT((fit->matrix() - kT.matrix()).norm(), 1e-9);
  const std::array<Eigen::Vector3d, 3> line = {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 2),
                                               Eigen::Vector3d(0, 0, 4)};
  EXPECT_FALSE(fitTriangleRigid(line, b).has_value());
  EXPECT_FALSE(fitTriangleRigid(a, {kT * line[0], kT * line[1], kT * line[2]}).has_value());
  EXPECT_FALSE(fitTriangleRigid(a, {b[0], b[0], b[0]}).has_value());
}
