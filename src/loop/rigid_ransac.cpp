#include "loop/rigid_ransac.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace plslam {

SE3 umeyamaRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                 const std::vector<char>& select) {
  int n = 0;
  for (size_t i = 0; i < p_a.size(); ++i) n += select.empty() || select[i];
  if (n < 3) return SE3();
  Eigen::Matrix3Xd A(3, n), B(3, n);
  int c = 0;
  for (size_t i = 0; i < p_a.size(); ++i) {
    if (!select.empty() && !select[i]) continue;
    A.col(c) = p_a[i];
    B.col(c) = p_b[i];
    ++c;
  }
  const Eigen::Matrix4d T = Eigen::umeyama(B, A, false);
  if (!T.allFinite()) return SE3();
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  return SE3(Eigen::Quaterniond(R).normalized(), T.topRightCorner<3, 1>());
}

namespace {
bool isInlier(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const SE3& T, const RigidRansacOptions& o) {
  const double gate = o.threshold_m + o.depth_coeff * a.z() * a.z();
  return (a - T * b).squaredNorm() < gate * gate;
}
}  // namespace

RigidRansacResult ransacRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                              const RigidRansacOptions& o) {
  RigidRansacResult r;
  const int n = static_cast<int>(std::min(p_a.size(), p_b.size()));
  r.inliers.assign(n, 0);
  if (n < 3) return r;
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<char> best, cur(n);
  int best_count = 0;
  for (int it = 0; it < o.iterations; ++it) {
    const int i = pick(rng), j = pick(rng), k = pick(rng);
    if (i == j || j == k || i == k) continue;
    // Degenerate (near-collinear or tiny) samples say nothing about rotation.
    const Eigen::Vector3d e1 = p_b[j] - p_b[i], e2 = p_b[k] - p_b[i];
    if (e1.cross(e2).norm() < 1e-3) continue;
    // The rigid distances of the sample must agree in both clouds.
    if (std::fabs((p_a[j] - p_a[i]).norm() - e1.norm()) > 0.1 || std::fabs((p_a[k] - p_a[i]).norm() - e2.norm()) > 0.1)
      continue;
    const SE3 T = umeyamaRigid({p_a[i], p_a[j], p_a[k]}, {p_b[i], p_b[j], p_b[k]});
    int count = 0;
    for (int m = 0; m < n; ++m) count += cur[m] = isInlier(p_a[m], p_b[m], T, o);
    if (count > best_count) best_count = count, best = cur;
  }
  if (best_count < 3) return r;
  SE3 T;
  for (int round = 0; round < std::max(1, o.refine_rounds); ++round) {
    T = umeyamaRigid(p_a, p_b, best);
    int count = 0;
    for (int m = 0; m < n; ++m) count += cur[m] = isInlier(p_a[m], p_b[m], T, o);
    if (count < 3) break;
    const bool same = cur == best;
    best = cur;
    best_count = count;
    if (same) break;
  }
  T = umeyamaRigid(p_a, p_b, best);
  double sq = 0;
  for (int m = 0; m < n; ++m)
    if (best[m]) sq += (p_a[m] - T * p_b[m]).squaredNorm();
  r.ok = true;
  r.T_a_b = T;
  r.inliers = best;
  r.inlier_count = best_count;
  r.rmse_m = std::sqrt(sq / best_count);
  return r;
}

}  // namespace plslam
