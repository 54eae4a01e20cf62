// Rigid 3D-3D registration: Umeyama on exact data, RANSAC with outliers.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "loop/rigid_ransac.h"

using namespace plslam;

namespace {
SE3 someTransform() {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, -1, 0.2).normalized())),
             Eigen::Vector3d(0.5, -0.2, 0.3));
}
}  // namespace

TEST(RigidRansac, UmeyamaRecoversAnExactTransform) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  const SE3 T = someTransform();
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 20; ++i) {
    b.emplace_back(u(rng), u(rng), 2 + u(rng));
    a.push_back(T * b.back());
  }
  const SE3 est = umeyamaRigid(a, b);
  EXPECT_LT((est.translation() - T.translation()).norm(), 1e-9);
  EXPECT_LT(est.quaternion().angularDistance(T.quaternion()), 1e-9);
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
