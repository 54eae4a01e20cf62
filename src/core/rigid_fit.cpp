#include "core/rigid_fit.h"

#include <Eigen/SVD>

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

}  // namespace plslam
