#include "core/rigid_fit.h"

#include <Eigen/SVD>
#include <cmath>

namespace plslam {

std::optional<RigidFit> fitRigid(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                                 const std::vector<double>& weights) {
  const size_t n = src.size();
  if (n < 3 || dst.size() != n || (!weights.empty() && weights.size() != n)) return std::nullopt;
  double wsum = 0;
  Eigen::Vector3d cs = Eigen::Vector3d::Zero(), cd = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    wsum += w;
    cs += w * src[i];
    cd += w * dst[i];
  }
  if (!(wsum > 0)) return std::nullopt;
  cs /= wsum;
  cd /= wsum;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    H += w * (src[i] - cs) * (dst[i] - cd).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sv = svd.singularValues();
  RigidFit fit;
  if (sv(0) > 1e-12) fit.rank = 1 + (sv(1) >= 1e-6 * sv(0)) + (sv(2) >= 1e-6 * sv(0));
  const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((V * U.transpose()).determinant() < 0) D(2, 2) = -1;  // the proper rotation, not its mirror image
  const Eigen::Matrix3d R = V * D * U.transpose();
  fit.T = SE3(R, cd - R * cs);
  return fit;
}

std::optional<SE3> fitUniqueRigid(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                                  const std::vector<double>& weights) {
  const std::optional<RigidFit> fit = fitRigid(src, dst, weights);
  if (!fit || !fit->unique()) return std::nullopt;
  return fit->T;
}

namespace {
/// An orthonormal frame of a triangle's plane: x along its first edge, n its unit normal.
struct PlaneFrame {
  Eigen::Vector3d x, y, n;
};

std::optional<PlaneFrame> planeOf(const std::array<Eigen::Vector3d, 3>& p) {
  const Eigen::Vector3d e1 = p[1] - p[0], e2 = p[2] - p[0];
  const Eigen::Vector3d normal = e1.cross(e2);
  const double area2 = normal.norm();
  if (!(area2 > 1e-12 * e1.norm() * e2.norm())) return std::nullopt;  // collinear or coincident points
  PlaneFrame f;
  f.x = e1.normalized();
  f.n = normal / area2;
  f.y = f.n.cross(f.x);
  return f;
}
}  // namespace

std::optional<SE3> fitTriangleRigid(const std::array<Eigen::Vector3d, 3>& src,
                                    const std::array<Eigen::Vector3d, 3>& dst) {
  const std::optional<PlaneFrame> fs = planeOf(src), fd = planeOf(dst);
  if (!fs || !fd) return std::nullopt;
  const Eigen::Vector3d cs = (src[0] + src[1] + src[2]) / 3.0, cd = (dst[0] + dst[1] + dst[2]) / 3.0;
  // K: the cross-covariance in plane coordinates; the fit maximises trace(Q * K) over 2-D
  // orthogonal Q. Each frame follows its own triangle's winding, so both triangles turn
  // counter-clockwise in their frames and det K > 0 (Cauchy-Binet over the equal signed areas):
  // the best Q is always a rotation, p = sigma0 + sigma1 and q = sigma0 - sigma1 of K.
  Eigen::Matrix2d K = Eigen::Matrix2d::Zero();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d a = src[i] - cs, b = dst[i] - cd;
    K += Eigen::Vector2d(fs->x.dot(a), fs->y.dot(a)) * Eigen::Vector2d(fd->x.dot(b), fd->y.dot(b)).transpose();
  }
  const double p = std::hypot(K(0, 0) + K(1, 1), K(0, 1) - K(1, 0));
  const double q = std::hypot(K(0, 0) - K(1, 1), K(0, 1) + K(1, 0));
  if (!(p + q > 2e-12) || p - q < 1e-6 * (p + q)) return std::nullopt;  // fitRigid's rank test on sigma0, sigma1
  const double c = (K(0, 0) + K(1, 1)) / p, s = (K(0, 1) - K(1, 0)) / p;
  Eigen::Matrix2d Q;
  Q << c, -s, s, c;
  Eigen::Matrix<double, 3, 2> A, B;
  A << fs->x, fs->y;
  B << fd->x, fd->y;
  const Eigen::Matrix3d R = B * Q * A.transpose() + fd->n * fs->n.transpose();
  return SE3(R, cd - R * cs);
}

}  // namespace plslam
