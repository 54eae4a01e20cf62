#include <gtest/gtest.h>

#include "core/se3.h"

using plslam::SE3;

TEST(SE3, ComposeWithInverseIsIdentity) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.3, -0.2, 1.5, 0.4, -0.7, 0.25;
  const SE3 T = SE3::exp(xi);
  const SE3 I = T * T.inverse();
  EXPECT_LT(I.translation().norm(), 1e-12);
  EXPECT_LT(I.angle(), 1e-7);
}

TEST(SE3, ExpLogRoundTrip) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << -1.0, 0.5, 2.0, 0.1, 2.5, -0.3;
  const Eigen::Matrix<double, 6, 1> back = SE3::exp(xi).log();
  EXPECT_LT((back - xi).norm(), 1e-9);
}

TEST(SE3, ActsAsTaB) {
  // T_a_b with b translated by +1 in x of a: the origin of b is at x = 1 in a.
  const SE3 T_a_b(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
  EXPECT_NEAR((T_a_b * Eigen::Vector3d::Zero()).x(), 1.0, 1e-15);
  const SE3 rot(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())), Eigen::Vector3d::Zero());
  const Eigen::Vector3d p = rot * Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR(p.y(), 1.0, 1e-12);
  EXPECT_NEAR(rot.angle(), M_PI / 2, 1e-12);
}

TEST(SE3, MatrixRoundTrip) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.1, 0.2, 0.3, -0.5, 0.2, 0.9;
  const SE3 T = SE3::exp(xi);
  const SE3 U(T.matrix());
  EXPECT_LT((T.matrix() - U.matrix()).norm(), 1e-12);
}
