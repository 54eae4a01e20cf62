#include "core/se3.h"

#include <algorithm>
#include <cmath>

namespace plslam {

namespace {
// Left Jacobian of SO(3); maps the translation part of a twist.
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = hat(phi);
  if (theta < 1e-8) return Eigen::Matrix3d::Identity() + 0.5 * K;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * K +
         (theta - std::sin(theta)) / (t2 * theta) * K * K;
}
}  // namespace

SE3 SE3::exp(const Eigen::Matrix<double, 6, 1>& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  const double theta = phi.norm();
  Eigen::Quaterniond q = theta < 1e-12 ? Eigen::Quaterniond::Identity()
                                       : Eigen::Quaterniond(Eigen::AngleAxisd(theta, phi / theta));
  return SE3(q, leftJacobian(phi) * rho);
}

Eigen::Matrix<double, 6, 1> SE3::log() const {
  const Eigen::AngleAxisd aa(q_);
  Eigen::Vector3d phi = aa.axis() * aa.angle();
  if (aa.angle() > M_PI) phi = aa.axis() * (aa.angle() - 2.0 * M_PI);
  Eigen::Matrix<double, 6, 1> xi;
  xi.head<3>() = leftJacobian(phi).inverse() * t_;
  xi.tail<3>() = phi;
  return xi;
}

Eigen::Matrix4d SE3::matrix() const {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = rotation();
  T.block<3, 1>(0, 3) = t_;
  return T;
}

double SE3::angle() const {
  const double w = std::min(1.0, std::abs(q_.w()));
  return 2.0 * std::acos(w);
}

}  // namespace plslam
