#include "loop/rigid_ransac.h"

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <random>

#include "core/rigid_fit.h"

namespace plslam {

namespace {
/// The rigid fit p_a ~ T * p_b over the selected pairs (all when `select` is empty); nullopt
/// when they do not fix it (fewer than three, or collinear).
std::optional<SE3> fitSelected(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                               const std::vector<char>& select) {
  std::vector<Eigen::Vector3d> a, b;
  for (size_t i = 0; i < p_a.size(); ++i)
    if (select.empty() || select[i]) a.push_back(p_a[i]), b.push_back(p_b[i]);
  return fitUniqueRigid(b, a);
}

double gate(const Eigen::Vector3d& a, const RigidRansacOptions& o) { return o.threshold_m + o.depth_coeff * a.z() * a.z(); }

bool isInlier(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const SE3& T, const RigidRansacOptions& o) {
  const double g = gate(a, o);
  return (a - T * b).squaredNorm() < g * g;
}

/// Component of x - on_line perpendicular to the unit direction d.
Eigen::Vector3d offLine(const Eigen::Vector3d& x, const Eigen::Vector3d& on_line, const Eigen::Vector3d& d) {
  const Eigen::Vector3d v = x - on_line;
  return v - d * d.dot(v);
}
}  // namespace

bool segmentsAgree(const SegmentPair3D& l, const SE3& T, const RigidRansacOptions& o) {
  const Eigen::Vector3d da = (l.q_a - l.p_a).normalized();
  const Eigen::Vector3d p = T * l.p_b, q = T * l.q_b;
  const Eigen::Vector3d db = (q - p).normalized();
  if (std::fabs(da.dot(db)) < std::cos(o.line_angle_deg * M_PI / 180.0)) return false;
  const double gp = gate(p, o), gq = gate(q, o);
  return offLine(p, l.p_a, da).squaredNorm() < gp * gp && offLine(q, l.p_a, da).squaredNorm() < gq * gq;
}

SE3 refineRigid(const SE3& T0, const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                const std::vector<char>& point_select, const std::vector<SegmentPair3D>& lines,
                const std::vector<char>& line_select, int iterations) {
  SE3 T = T0;
  for (int it = 0; it < iterations; ++it) {
    // Left perturbation: y' = y + w x y + v for the twist (w, v).
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    auto add = [&](const Eigen::Matrix3d& P, const Eigen::Vector3d& y, const Eigen::Vector3d& r) {
      Eigen::Matrix<double, 3, 6> J;
      J << -hat(y), Eigen::Matrix3d::Identity();
      J = P * J;
      H += J.transpose() * J;
      g += J.transpose() * r;
    };
    for (size_t i = 0; i < std::min(p_a.size(), p_b.size()); ++i) {
      if (!point_select.empty() && !point_select[i]) continue;
      const Eigen::Vector3d y = T * p_b[i];
      add(Eigen::Matrix3d::Identity(), y, y - p_a[i]);
    }
    for (size_t i = 0; i < lines.size(); ++i) {
      if (!line_select.empty() && !line_select[i]) continue;
      const Eigen::Vector3d d = (lines[i].q_a - lines[i].p_a).normalized();
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - d * d.transpose();
      for (const Eigen::Vector3d& e : {lines[i].p_b, lines[i].q_b}) {
        const Eigen::Vector3d y = T * e;
        add(P, y, offLine(y, lines[i].p_a, d));
      }
    }
    const Eigen::Matrix<double, 6, 1> step = H.ldlt().solve(-g);
    if (!step.allFinite()) break;
    const Eigen::Vector3d w = step.head<3>(), v = step.tail<3>();
    const Eigen::Quaterniond dq = w.norm() > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized()))
                                               : Eigen::Quaterniond::Identity();
    T = SE3(dq * T.quaternion(), dq * T.translation() + v);
    if (step.norm() < 1e-10) break;
  }
  return T;
}

RigidRansacResult ransacRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                              const RigidRansacOptions& o) {
  return ransacRigid(p_a, p_b, {}, o);
}

RigidRansacResult ransacRigid(const std::vector<Eigen::Vector3d>& p_a, const std::vector<Eigen::Vector3d>& p_b,
                              const std::vector<SegmentPair3D>& lines, const RigidRansacOptions& o) {
  RigidRansacResult r;
  const int n = static_cast<int>(std::min(p_a.size(), p_b.size()));
  const int nl = static_cast<int>(lines.size());
  r.inliers.assign(n, 0);
  r.line_inliers.assign(nl, 0);
  if (n < 3) return r;
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<char> best, cur(n), best_lines(nl), cur_lines(nl);
  int best_total = 0, best_points = 0;
  SE3 best_sample;
  auto consensus = [&](const SE3& T) {
    int points = 0, total = 0;
    for (int m = 0; m < n; ++m) points += cur[m] = isInlier(p_a[m], p_b[m], T, o);
    total = points;
    for (int m = 0; m < nl; ++m) total += cur_lines[m] = segmentsAgree(lines[m], T, o);
    return std::make_pair(points, total);
  };
  for (int it = 0; it < o.iterations; ++it) {
    const int i = pick(rng), j = pick(rng), k = pick(rng);
    if (i == j || j == k || i == k) continue;
    // Degenerate (near-collinear or tiny) samples say nothing about rotation.
    const Eigen::Vector3d e1 = p_b[j] - p_b[i], e2 = p_b[k] - p_b[i];
    if (e1.cross(e2).norm() < 1e-3) continue;
    // The rigid distances of the sample must agree in both clouds.
    if (std::fabs((p_a[j] - p_a[i]).norm() - e1.norm()) > 0.1 || std::fabs((p_a[k] - p_a[i]).norm() - e2.norm()) > 0.1)
      continue;
    const std::optional<SE3> T = fitSelected({p_a[i], p_a[j], p_a[k]}, {p_b[i], p_b[j], p_b[k]}, {});
    if (!T) continue;
    const auto [points, total] = consensus(*T);
    if (points >= 3 && total > best_total)
      best_total = total, best_points = points, best = cur, best_lines = cur_lines, best_sample = *T;
  }
  if (best_points < 3) return r;
  // A refit on collinear inliers fixes no rotation: the pose they agreed with stays.
  auto fit = [&](const SE3& before) {
    const SE3 T = fitSelected(p_a, p_b, best).value_or(before);
    bool any_line = false;
    for (char c : best_lines) any_line = any_line || c;
    return any_line ? refineRigid(T, p_a, p_b, best, lines, best_lines) : T;
  };
  SE3 T = best_sample;
  for (int round = 0; round < std::max(1, o.refine_rounds); ++round) {
    T = fit(T);
    const auto [points, total] = consensus(T);
    if (points < 3) break;
    const bool same = cur == best && cur_lines == best_lines;
    best = cur;
    best_lines = cur_lines;
    best_points = points;
    best_total = total;
    if (same) break;
  }
  T = fit(T);
  double sq = 0;
  for (int m = 0; m < n; ++m)
    if (best[m]) sq += (p_a[m] - T * p_b[m]).squaredNorm();
  r.ok = true;
  r.T_a_b = T;
  r.inliers = best;
  r.inlier_count = best_points;
  r.line_inliers = best_lines;
  r.line_inlier_count = best_total - best_points;
  r.rmse_m = std::sqrt(sq / best_points);
  return r;
}

}  // namespace plslam
