// Ceres residuals and manifolds of the optimisers. Internal to optim: include it only from
// optim sources and tests/optim, never from another module's headers (Ceres stays in optim).
//
// Pose block layout (7 doubles): qx qy qz qw tx ty tz, Eigen's quaternion order.
// BA: the block holds T_c_w (world to camera), with PoseLiftManifold and analytic Jacobians.
// Pose-only: a Euclidean 6-dof increment around a T_c_w base (PoseOnlyBatchCost).
// Pose graph: the block holds T_w_c, with PoseManifold (unit quaternion x R^3) and autodiff.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/se3.h"

namespace plslam::optim_internal {

constexpr int kPoseSize = 7;
constexpr int kPointSize = 3;
constexpr int kLineSize = 6;  // P (3) then Q (3), world endpoints

using PoseManifold = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

inline void poseToBlock(const SE3& T, double* block) {
  const Eigen::Quaterniond& q = T.quaternion();
  block[0] = q.x(), block[1] = q.y(), block[2] = q.z(), block[3] = q.w();
  block[4] = T.translation().x(), block[5] = T.translation().y(), block[6] = T.translation().z();
}

inline SE3 blockToPose(const double* block) {
  return SE3(Eigen::Quaterniond(block[3], block[0], block[1], block[2]), Eigen::Vector3d(block[4], block[5], block[6]));
}

struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

/// p_a = T_a_b * p_b for a pose block holding T_a_b.
template <typename T>
Eigen::Matrix<T, 3, 1> transformPoint(const T* pose, const Eigen::Matrix<T, 3, 1>& p_b) {
  const Eigen::Map<const Eigen::Quaternion<T>> q(pose);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(pose + 4);
  return q * p_b + t;
}

/// Ideal pinhole projection; false when the point is closer than min_depth to the image plane.
template <typename T>
bool projectIdeal(const Intrinsics& K, const Eigen::Matrix<T, 3, 1>& p_c, double min_depth, T* uv) {
  if (!(p_c.z() > T(min_depth))) return false;
  const T inv_z = T(1.0) / p_c.z();
  uv[0] = K.fx * p_c.x() * inv_z + K.cx;
  uv[1] = K.fy * p_c.y() * inv_z + K.cy;
  return true;
}

/// Whitened point residual: (projection - uv) / sigma, and for N == 3 also
/// (z_pred - z_obs) / sigma_z. operator() is the plain reference evaluation (used to classify
/// observations); the analytic costs below compute the same residuals with Jacobians.
template <int N>
struct PointTerm {
  static_assert(N == 2 || N == 3, "a point term has 2 (pixel) or 3 (pixel + depth) residuals");
  Intrinsics K;
  Eigen::Vector2d uv;
  double inv_sigma = 1.0;
  double depth = 0.0;        // observed depth, metres (N == 3 only)
  double inv_sigma_z = 0.0;  // 1 / sigma_z (N == 3 only)
  double min_depth = 1e-3;

  template <typename T>
  bool operator()(const T* pose_c_w, const Eigen::Matrix<T, 3, 1>& p_w, T* r) const {
    const Eigen::Matrix<T, 3, 1> p_c = transformPoint(pose_c_w, p_w);
    T proj[2];
    if (!projectIdeal(K, p_c, min_depth, proj)) return false;
    r[0] = (proj[0] - uv.x()) * inv_sigma;
    r[1] = (proj[1] - uv.y()) * inv_sigma;
    if constexpr (N == 3) r[2] = (p_c.z() - depth) * inv_sigma_z;
    return true;
  }
};

/// Whitened line residual: signed pixel distances of the projections of P and Q to the
/// observed infinite 2D line l (a^2 + b^2 = 1), divided by sigma.
struct LineTerm {
  Intrinsics K;
  Eigen::Vector3d l;
  double inv_sigma = 1.0;
  double min_depth = 1e-3;

  template <typename T>
  bool operator()(const T* pose_c_w, const Eigen::Matrix<T, 3, 1>& P_w, const Eigen::Matrix<T, 3, 1>& Q_w,
                  T* r) const {
    T p[2], q[2];
    if (!projectIdeal(K, transformPoint(pose_c_w, P_w), min_depth, p)) return false;
    if (!projectIdeal(K, transformPoint(pose_c_w, Q_w), min_depth, q)) return false;
    r[0] = (l.x() * p[0] + l.y() * p[1] + l.z()) * inv_sigma;
    r[1] = (l.x() * q[0] + l.y() * q[1] + l.z()) * inv_sigma;
    return true;
  }
};

/// Pose manifold of the projection costs, on a block holding T_c_w: a LEFT perturbation in
/// the camera frame, x + [rho; phi] = (Exp(phi) R, Exp(phi) t + rho), so a camera point moves
/// as p_c + rho + phi x p_c. The costs below give analytic Jacobians in this tangent space
/// directly, "lifted" into the 7 ambient columns (first 6 = tangent, last = 0), and
/// PlusJacobian is [I6; 0] accordingly. Only costs following this convention may share a
/// block with it (all projection costs here do; the autodiff pose-graph cost does not).
class PoseLiftManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseSize; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    plus(x, delta, x_plus_delta);
    return true;
  }
  static void plus(const double* x, const double* delta, double* x_plus_delta) {
    const Eigen::Map<const Eigen::Quaterniond> q(x);
    const Eigen::Map<const Eigen::Vector3d> t(x + 4), rho(delta), phi(delta + 3);
    const Eigen::Quaterniond dq = expQuaternion(phi);
    Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta);
    Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta + 4);
    q_out = (dq * q).normalized();
    t_out = dq * t + rho;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Eigen::Quaterniond> qy(y), qx(x);
    const Eigen::Map<const Eigen::Vector3d> ty(y + 4), tx(x + 4);
    const Eigen::AngleAxisd aa(qy * qx.conjugate());
    double angle = aa.angle();
    if (angle > M_PI) angle -= 2.0 * M_PI;
    const Eigen::Vector3d phi = aa.axis() * angle;
    Eigen::Vector3d::Map(y_minus_x) = ty - expQuaternion(phi) * tx;
    Eigen::Vector3d::Map(y_minus_x + 3) = phi;
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
  }
  static Eigen::Quaterniond expQuaternion(const Eigen::Vector3d& phi) {
    const double theta = phi.norm();
    if (theta < 1e-10) return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z()).normalized();
    return Eigen::Quaterniond(Eigen::AngleAxisd(theta, phi / theta));
  }
};

// Analytic projection costs. Each carries an optional `active` flag (owned by the caller,
// stable address): when it is 0 the residuals and Jacobians are zero, so one problem can be
// re-solved with outliers switched off instead of being rebuilt.
namespace detail {

inline bool switchedOff(const std::uint8_t* active, int n_res, double* r, double* const* J, const int* block_sizes,
                        int n_blocks) {
  if (active == nullptr || *active) return false;
  std::fill(r, r + n_res, 0.0);
  if (J)
    for (int b = 0; b < n_blocks; ++b)
      if (J[b]) std::fill(J[b], J[b] + n_res * block_sizes[b], 0.0);
  return true;
}

// Writes [dr_dpc, -dr_dpc [p_c]x, 0] into a row-major N x 7 pose Jacobian.
template <int N>
void writePoseJacobian(const Eigen::Matrix<double, N, 3>& dr_dpc, const Eigen::Vector3d& p_c, double* J_pose) {
  Eigen::Map<Eigen::Matrix<double, N, 7, Eigen::RowMajor>> J(J_pose);
  J.template leftCols<3>() = dr_dpc;
  J.template middleCols<3>(3) = -dr_dpc * hat(p_c);
  J.col(6).setZero();
}

// Point projection (and depth for N == 3) at T_c_w = pose; Jacobians optional.
template <int N>
bool evaluatePoint(const PointTerm<N>& t, const double* pose, const Eigen::Vector3d& p_w, double* r, double* J_pose,
                   double* J_point) {
  const Eigen::Map<const Eigen::Quaterniond> q(pose);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Vector3d p_c = R * p_w + Eigen::Map<const Eigen::Vector3d>(pose + 4);
  if (!(p_c.z() > t.min_depth)) return false;
  const double iz = 1.0 / p_c.z();
  r[0] = (t.K.fx * p_c.x() * iz + t.K.cx - t.uv.x()) * t.inv_sigma;
  r[1] = (t.K.fy * p_c.y() * iz + t.K.cy - t.uv.y()) * t.inv_sigma;
  if constexpr (N == 3) r[2] = (p_c.z() - t.depth) * t.inv_sigma_z;
  if (!J_pose && !J_point) return true;
  Eigen::Matrix<double, N, 3> dr_dpc;
  dr_dpc.row(0) << t.K.fx * iz * t.inv_sigma, 0.0, -t.K.fx * p_c.x() * iz * iz * t.inv_sigma;
  dr_dpc.row(1) << 0.0, t.K.fy * iz * t.inv_sigma, -t.K.fy * p_c.y() * iz * iz * t.inv_sigma;
  if constexpr (N == 3) dr_dpc.row(2) << 0.0, 0.0, t.inv_sigma_z;
  if (J_pose) writePoseJacobian<N>(dr_dpc, p_c, J_pose);
  if (J_point) {
    Eigen::Map<Eigen::Matrix<double, N, 3, Eigen::RowMajor>> Jx(J_point);
    Jx = dr_dpc * R;
  }
  return true;
}

// Point-to-line distances of the projections of P and Q; Jacobians optional
// (J_line is 2 x 6 over [P; Q]).
inline bool evaluateLine(const LineTerm& t, const double* pose, const Eigen::Vector3d& P_w, const Eigen::Vector3d& Q_w,
                         double* r, double* J_pose, double* J_line) {
  const Eigen::Map<const Eigen::Quaterniond> q(pose);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> trans(pose + 4);
  Eigen::Matrix<double, 2, 7, Eigen::RowMajor> Jp;
  Eigen::Matrix<double, 2, 6, Eigen::RowMajor> Jl;
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector3d p_c = R * (e == 0 ? P_w : Q_w) + trans;
    if (!(p_c.z() > t.min_depth)) return false;
    const double iz = 1.0 / p_c.z();
    const double u = t.K.fx * p_c.x() * iz + t.K.cx, v = t.K.fy * p_c.y() * iz + t.K.cy;
    r[e] = (t.l.x() * u + t.l.y() * v + t.l.z()) * t.inv_sigma;
    if (!J_pose && !J_line) continue;
    Eigen::Matrix<double, 1, 3> dr_dpc;
    dr_dpc << t.l.x() * t.K.fx * iz, t.l.y() * t.K.fy * iz,
        -(t.l.x() * t.K.fx * p_c.x() + t.l.y() * t.K.fy * p_c.y()) * iz * iz;
    dr_dpc *= t.inv_sigma;
    Jp.row(e) << dr_dpc, -dr_dpc * hat(p_c), 0.0;
    Jl.row(e).setZero();
    Jl.row(e).segment<3>(3 * e) = dr_dpc * R;
  }
  if (J_pose) Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>>{J_pose} = Jp;
  if (J_line) Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>>{J_line} = Jl;
  return true;
}

}  // namespace detail

/// BA point cost: pose (T_c_w, PoseLiftManifold) and world point.
template <int N>
class PointCost final : public ceres::SizedCostFunction<N, kPoseSize, kPointSize> {
 public:
  PointCost(const PointTerm<N>& term, const std::uint8_t* active) : term_(term), active_(active) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    static constexpr int kSizes[2] = {kPoseSize, kPointSize};
    if (detail::switchedOff(active_, N, r, J, kSizes, 2)) return true;
    return detail::evaluatePoint<N>(term_, p[0], Eigen::Vector3d(p[1]), r, J ? J[0] : nullptr, J ? J[1] : nullptr);
  }
  const PointTerm<N>& term() const { return term_; }

 private:
  PointTerm<N> term_;
  const std::uint8_t* active_;
};

/// BA line cost: pose (T_c_w, PoseLiftManifold) and the line's world endpoints [P; Q].
class LineCost final : public ceres::SizedCostFunction<2, kPoseSize, kLineSize> {
 public:
  LineCost(const LineTerm& term, const std::uint8_t* active) : term_(term), active_(active) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    static constexpr int kSizes[2] = {kPoseSize, kLineSize};
    if (detail::switchedOff(active_, 2, r, J, kSizes, 2)) return true;
    return detail::evaluateLine(term_, p[0], Eigen::Vector3d(p[1]), Eigen::Vector3d(p[1] + 3), r,
                                J ? J[0] : nullptr, J ? J[1] : nullptr);
  }

 private:
  LineTerm term_;
  const std::uint8_t* active_;
};

/// All observations of a pose-only problem in ONE residual block: per-observation Ceres
/// residual blocks cost more in bookkeeping than the projections themselves. The parameter
/// is a Euclidean 6-vector delta = [rho; phi] around a base pose (T_c_w, pose block layout)
/// owned by the caller: T_c_w = PoseLiftManifold::Plus(base, delta), with the exact Jacobian
/// (SO(3) left Jacobian included), so no manifold is needed; the caller folds delta into the
/// base between solves.
///
/// Robustness is iteratively reweighted least squares: reweight(pose) fixes, per observation,
/// w = sqrt(rho'(s)) of the Huber loss at that pose (s = squared whitened residual), and the
/// block then holds w * r with Jacobian w * J. At the reweighting pose the gradient equals the
/// Huber cost's (w^2 J^T r = rho' J^T r); between reweightings it is a plain weighted least
/// squares, which Gauss-Newton solves in a few iterations. The pose optimiser reweights once
/// per round (and uses unit weights in its final, non-robust round, as ORB-SLAM does).
/// Switched-off observations (active == 0) give zero rows.
class PoseOnlyBatchCost final : public ceres::CostFunction {
 public:
  /// huber2 / huber3: Huber thresholds on the whitened residual norm of 2- and 3-row
  /// observations; 0 disables the loss.
  PoseOnlyBatchCost(const double* base, double huber2, double huber3) : base_(base), huber2_(huber2), huber3_(huber3) {
    mutable_parameter_block_sizes()->assign(1, 6);
  }
  void addPoint(const PointTerm<2>& t, const Eigen::Vector3d& p_w, const std::uint8_t* active) {
    mono_.push_back({t, p_w, active, rows_, 1.0});
    grow(2);
  }
  void addPoint(const PointTerm<3>& t, const Eigen::Vector3d& p_w, const std::uint8_t* active) {
    rgbd_.push_back({t, p_w, active, rows_, 1.0});
    grow(3);
  }
  void addLine(const LineTerm& t, const Eigen::Vector3d& P_w, const Eigen::Vector3d& Q_w,
               const std::uint8_t* active) {
    lines_.push_back({t, P_w, Q_w, active, rows_, 1.0});
    grow(2);
  }

  /// Sets the Huber weights at the base pose (robust = true) or all weights to 1 (robust = false).
  void reweight(bool robust) {
    const double* pose = base_;
    auto weightOf = [](double delta, double s) { return s > delta * delta ? std::sqrt(delta / std::sqrt(s)) : 1.0; };
    double r[3];
    for (auto& o : mono_)
      o.weight = robust && detail::evaluatePoint<2>(o.term, pose, o.p_w, r, nullptr, nullptr)
                     ? weightOf(huber2_, r[0] * r[0] + r[1] * r[1])
                     : 1.0;
    for (auto& o : rgbd_)
      o.weight = robust && detail::evaluatePoint<3>(o.term, pose, o.p_w, r, nullptr, nullptr)
                     ? weightOf(huber3_, r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
                     : 1.0;
    for (auto& o : lines_)
      o.weight = robust && detail::evaluateLine(o.term, pose, o.P_w, o.Q_w, r, nullptr, nullptr)
                     ? weightOf(huber2_, r[0] * r[0] + r[1] * r[1])
                     : 1.0;
  }
  /// Weight of the k-th observation without depth (for tests).
  double monoWeight(size_t k) const { return mono_[k].weight; }

  bool Evaluate(double const* const* p, double* r, double** J) const override {
    double pose[kPoseSize];
    PoseLiftManifold::plus(base_, p[0], pose);
    // dp_c/dphi = -[p_c - rho]x J_l(phi): the left-perturbation Jacobians of the terms
    // (-[p_c]x) are corrected by the rho shift and J_l below.
    const Eigen::Map<const Eigen::Vector3d> rho(p[0]), phi(p[0] + 3);
    const Eigen::Matrix3d Jl = leftJacobianSO3(phi);
    double* Jp = J ? J[0] : nullptr;
    auto convert = [&](int n, const double* J7, double* J6) {  // N x 7 lifted -> N x 6 exact
      for (int i = 0; i < n; ++i) {
        const Eigen::Map<const Eigen::Matrix<double, 1, 7>> a(J7 + 7 * i);
        Eigen::Map<Eigen::Matrix<double, 1, 6>> b(J6 + 6 * i);
        const Eigen::Matrix<double, 1, 3> dr_dpc = a.head<3>();
        b.head<3>() = dr_dpc;
        // a.segment(3) = -dr_dpc [p_c]x; the exact term is -dr_dpc [p_c - rho]x J_l.
        b.tail<3>() = (a.segment<3>(3) + dr_dpc * hat(rho)) * Jl;
      }
    };
    double J7[3 * 7];
    auto run = [&](const auto& o, int n, auto eval) {
      double* Jo = Jp ? Jp + o.row * 6 : nullptr;
      double* ro = r + o.row;
      if (o.active && !*o.active) {
        std::fill(ro, ro + n, 0.0);
        if (Jo) std::fill(Jo, Jo + n * 6, 0.0);
        return true;
      }
      if (!eval(ro, Jo ? J7 : nullptr)) return false;
      if (Jo) convert(n, J7, Jo);
      if (o.weight != 1.0) {
        for (int i = 0; i < n; ++i) ro[i] *= o.weight;
        if (Jo)
          for (int i = 0; i < n * 6; ++i) Jo[i] *= o.weight;
      }
      return true;
    };
    for (const auto& o : mono_)
      if (!run(o, 2, [&](double* ro, double* Jo) { return detail::evaluatePoint<2>(o.term, pose, o.p_w, ro, Jo, nullptr); }))
        return false;
    for (const auto& o : rgbd_)
      if (!run(o, 3, [&](double* ro, double* Jo) { return detail::evaluatePoint<3>(o.term, pose, o.p_w, ro, Jo, nullptr); }))
        return false;
    for (const auto& o : lines_)
      if (!run(o, 2, [&](double* ro, double* Jo) {
            return detail::evaluateLine(o.term, pose, o.P_w, o.Q_w, ro, Jo, nullptr);
          }))
        return false;
    return true;
  }

  /// Left Jacobian of SO(3): Exp(phi + e) ~ Exp(J_l(phi) e) Exp(phi).
  static Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d K = hat(phi);
    if (theta < 1e-8) return Eigen::Matrix3d::Identity() + 0.5 * K;
    const double t2 = theta * theta;
    return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * K + (theta - std::sin(theta)) / (t2 * theta) * K * K;
  }

 private:
  template <int N>
  struct PointEntry {
    PointTerm<N> term;
    Eigen::Vector3d p_w;
    const std::uint8_t* active;
    int row;
    double weight;
  };
  struct LineEntry {
    LineTerm term;
    Eigen::Vector3d P_w, Q_w;
    const std::uint8_t* active;
    int row;
    double weight;
  };

  void grow(int n) {
    rows_ += n;
    set_num_residuals(rows_);
  }
  const double* base_;
  double huber2_, huber3_;
  int rows_ = 0;
  std::vector<PointEntry<2>> mono_;
  std::vector<PointEntry<3>> rgbd_;
  std::vector<LineEntry> lines_;
};

/// Gauge of a 3D segment: the point-to-line residuals do not see an endpoint sliding along
/// the line, so the line block (P, Q) moves only in the 4-dof subspace where each endpoint
/// stays in the plane through its initial position perpendicular to the initial direction d:
/// x + delta = (P + B delta[0..1], Q + B delta[2..3]) with B = two unit vectors normal to d.
/// Exactly the 4 dof of a 3D line, no prior, and no drift or shrinking along the line.
class LineGaugeManifold final : public ceres::Manifold {
 public:
  explicit LineGaugeManifold(const Eigen::Vector3d& d) {
    const Eigen::Vector3d n = d.normalized();
    Eigen::Index axis;
    n.cwiseAbs().minCoeff(&axis);  // the axis least aligned with d
    const Eigen::Vector3d u = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
    B_ << u, n.cross(u);
  }
  int AmbientSize() const override { return kLineSize; }
  int TangentSize() const override { return 4; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::Vector4d> dl(delta);
    Eigen::Map<Eigen::Matrix<double, 6, 1>> out(x_plus_delta);
    out = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(x);
    out.head<3>() += B_ * dl.head<2>();
    out.tail<3>() += B_ * dl.tail<2>();
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.block<3, 2>(0, 0) = B_;
    J.block<3, 2>(3, 2) = B_;
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Matrix<double, 6, 1> diff =
        Eigen::Map<const Eigen::Matrix<double, 6, 1>>(y) - Eigen::Map<const Eigen::Matrix<double, 6, 1>>(x);
    Eigen::Map<Eigen::Vector4d> out(y_minus_x);
    out.head<2>() = B_.transpose() * diff.head<3>();
    out.tail<2>() = B_.transpose() * diff.tail<3>();
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 4, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.block<2, 3>(0, 0) = B_.transpose();
    J.block<2, 3>(2, 3) = B_.transpose();
    return true;
  }

 private:
  Eigen::Matrix<double, 3, 2> B_;
};

/// Pose-graph edge on blocks holding T_w_i and T_w_j: with E = T_i_j_meas^-1 * T_i_w * T_w_j,
/// r = sqrt_info * [t(E); 2 vec(q(E))] (translation first, like SE3::log).
struct RelativePoseCost {
  Eigen::Quaterniond q_i_j;
  Eigen::Vector3d t_i_j;
  Eigen::Matrix<double, 6, 6> sqrt_info;

  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_w_i(pose_i), q_w_j(pose_j);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_w_i(pose_i + 4), t_w_j(pose_j + 4);
    const Eigen::Quaternion<T> q_i_w = q_w_i.conjugate();
    const Eigen::Quaternion<T> q_est = q_i_w * q_w_j;
    const Eigen::Matrix<T, 3, 1> t_est = q_i_w * (t_w_j - t_w_i);
    const Eigen::Quaternion<T> q_meas_inv = q_i_j.conjugate().cast<T>();
    Eigen::Quaternion<T> q_err = q_meas_inv * q_est;
    if (q_err.w() < T(0.0)) q_err.coeffs() = -q_err.coeffs();  // the short way round
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = q_meas_inv * (t_est - t_i_j.cast<T>());
    e.template tail<3>() = T(2.0) * q_err.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = sqrt_info.cast<T>() * e;
    return true;
  }
  static ceres::CostFunction* create(const RelativePoseCost& c) {
    return new ceres::AutoDiffCostFunction<RelativePoseCost, 6, kPoseSize, kPoseSize>(new RelativePoseCost(c));
  }
};

}  // namespace plslam::optim_internal
