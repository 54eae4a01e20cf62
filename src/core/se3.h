// Rigid transforms. Convention: T_a_b maps points from frame b into frame a
// (p_a = T_a_b * p_b), the same as ViSP's aMb, so conversions need no inversion.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plslam {

class SE3 {
 public:
  SE3() : q_(Eigen::Quaterniond::Identity()), t_(Eigen::Vector3d::Zero()) {}
  SE3(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) : q_(q.normalized()), t_(t) {}
  SE3(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) : q_(Eigen::Quaterniond(R).normalized()), t_(t) {}
  /// From a 4x4 homogeneous matrix (the rotation block is re-orthonormalised).
  explicit SE3(const Eigen::Matrix4d& T) : SE3(Eigen::Matrix3d(T.block<3, 3>(0, 0)), Eigen::Vector3d(T.block<3, 1>(0, 3))) {}

  static SE3 identity() { return SE3(); }
  /// exp map of a twist [rho; phi] (translation first, rotation vector second).
  static SE3 exp(const Eigen::Matrix<double, 6, 1>& xi);
  /// Inverse of exp: [rho; phi].
  Eigen::Matrix<double, 6, 1> log() const;

  const Eigen::Quaterniond& quaternion() const { return q_; }
  Eigen::Matrix3d rotation() const { return q_.toRotationMatrix(); }
  const Eigen::Vector3d& translation() const { return t_; }
  Eigen::Matrix4d matrix() const;

  SE3 inverse() const {
    const Eigen::Quaterniond qi = q_.conjugate();
    return SE3(qi, -(qi * t_));
  }
  SE3 operator*(const SE3& o) const { return SE3(q_ * o.q_, t_ + q_ * o.t_); }
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return q_ * p + t_; }

  /// Rotation angle of this transform, radians in [0, pi].
  double angle() const;

 private:
  Eigen::Quaterniond q_;
  Eigen::Vector3d t_;
};

/// Skew-symmetric matrix of v: hat(v) * x == v.cross(x).
inline Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace plslam
