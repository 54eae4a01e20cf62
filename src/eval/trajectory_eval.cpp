#include "eval/trajectory_eval.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "core/error.h"
#include "core/rigid_fit.h"
#include "core/json.h"
#include "core/log.h"
#include "io/trajectory_file.h"

namespace plslam {

namespace {
const Logger kLog("eval");

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<double> seconds(const Trajectory& traj) {
  std::vector<double> s(traj.size());
  std::transform(traj.begin(), traj.end(), s.begin(), [](const StampedPose& p) { return stampSeconds(p.t_ns); });
  return s;
}
}  // namespace

Stats computeStats(const std::vector<double>& values) {
  Stats s;
  s.count = static_cast<int>(values.size());
  if (values.empty()) return s;
  const double n = static_cast<double>(values.size());
  double sum = 0, sum_sq = 0;
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);  // population standard deviation, as numpy.std
  s.median = median(values);
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  s.min = *lo;
  s.max = *hi;
  return s;
}

std::vector<StampMatch> associate(const Trajectory& gt, const Trajectory& est, double max_difference_s) {
  std::vector<TimeNs> a(gt.size()), b(est.size());
  std::transform(gt.begin(), gt.end(), a.begin(), [](const StampedPose& p) { return p.t_ns; });
  std::transform(est.begin(), est.end(), b.begin(), [](const StampedPose& p) { return p.t_ns; });
  return associateStamps(a, b, max_difference_s);
}

AteResult computeAte(const Trajectory& gt, const Trajectory& est, const std::vector<StampMatch>& pairs) {
  AteResult r;
  r.pairs = pairs;
  std::vector<Eigen::Vector3d> p_est, p_gt;
  for (const StampMatch& m : pairs) {
    p_gt.push_back(gt.at(m.first).T_w_c.translation());
    p_est.push_back(est.at(m.second).T_w_c.translation());
  }
  if (pairs.size() < 3) throw DataError(str("ATE needs at least 3 associated poses, got ", pairs.size()));
  // A trajectory along a straight line fixes no rotation about it; any of the equal fits will do.
  r.T_gt_est = fitRigid(p_est, p_gt)->T;
  const Eigen::Matrix3d R = r.T_gt_est.rotation();
  const Eigen::Vector3d t = r.T_gt_est.translation();
  r.errors.reserve(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) r.errors.push_back((R * p_est[k] + t - p_gt[k]).norm());
  r.stats = computeStats(r.errors);
  return r;
}

RpeResult computeRpe(const Trajectory& gt, const Trajectory& est, double delta_s) {
  RpeResult r;
  r.delta_s = delta_s;
  if (gt.size() < 2 || est.size() < 2) return r;
  const std::vector<double> t_gt = seconds(gt), t_est = seconds(est);
  std::vector<double> intervals(t_gt.size() - 1);
  for (size_t k = 0; k + 1 < t_gt.size(); ++k) intervals[k] = t_gt[k + 1] - t_gt[k];
  const double gt_max_time_difference = 2.0 * median(intervals);

  // 4x4 matrices and general inverses, as the reference script computes them.
  auto m = [](const SE3& T) { return T.matrix(); };
  auto ominus = [](const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) -> Eigen::Matrix4d { return a.inverse() * b; };
  std::vector<double> trans, rot_deg;
  const size_t last = est.size() - 1;
  for (size_t i = 0; i < est.size(); ++i) {
    const size_t j = findClosestIndex(t_est, t_est[i] + delta_s);
    if (j == last) continue;
    const size_t gi = findClosestIndex(t_gt, t_est[i]);
    const size_t gj = findClosestIndex(t_gt, t_est[j]);
    if (std::abs(t_gt[gi] - t_est[i]) > gt_max_time_difference || std::abs(t_gt[gj] - t_est[j]) > gt_max_time_difference)
      continue;
    const Eigen::Matrix4d E =
        ominus(ominus(m(est[j].T_w_c), m(est[i].T_w_c)), ominus(m(gt[gj].T_w_c), m(gt[gi].T_w_c)));
    trans.push_back(E.block<3, 1>(0, 3).norm());
    const double c = std::clamp((E.block<3, 3>(0, 0).trace() - 1.0) / 2.0, -1.0, 1.0);
    rot_deg.push_back(std::acos(c) * 180.0 / M_PI);
  }
  r.pairs = static_cast<int>(trans.size());
  r.trans = computeStats(trans);
  r.rot_deg = computeStats(rot_deg);
  return r;
}

EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options, const std::string& gt_name,
                    const std::string& est_name) {
  if (!(options.max_difference_s > 0)) throw ConfigError(str("max_difference must be positive, got ", options.max_difference_s));
  if (!(options.rpe_delta_s > 0)) throw ConfigError(str("RPE delta must be positive, got ", options.rpe_delta_s));
  EvalResult r;
  r.gt_name = gt_name;
  r.est_name = est_name;
  r.gt_poses = static_cast<int>(gt.size());
  r.est_poses = static_cast<int>(est.size());
  const std::vector<StampMatch> pairs = associate(gt, est, options.max_difference_s);
  if (pairs.size() < 3) {
    std::string span;
    if (!gt.empty() && !est.empty())
      span = str(" (ground truth ", formatSecondsStamp(gt.front().t_ns), "..", formatSecondsStamp(gt.back().t_ns),
                 " s, estimate ", formatSecondsStamp(est.front().t_ns), "..", formatSecondsStamp(est.back().t_ns), " s)");
    throw DataError(str(est_name, " vs ", gt_name, ": ", pairs.size(), " pose(s) associated within ",
                        options.max_difference_s, " s, at least 3 needed", span,
                        pairs.empty() ? ": the stamps do not overlap; are these files of the same sequence?" : ""));
  }
  r.ate = computeAte(gt, est, pairs);
  r.rpe = computeRpe(gt, est, options.rpe_delta_s);
  if (r.rpe.pairs == 0)
    kLog.warn(str(est_name, ": no RPE pair over ", options.rpe_delta_s, " s (trajectory too short?)"));
  return r;
}

EvalResult evaluateFiles(const std::string& gt_path, const std::string& est_path, const EvalOptions& options) {
  const Trajectory gt = readTumTrajectory(gt_path);
  const Trajectory est = readTumTrajectory(est_path);
  return evaluate(gt, est, options, gt_path, est_path);
}

namespace {

Json figuresJson(const Stats& a) {
  return {{"rmse", a.rmse}, {"mean", a.mean}, {"median", a.median}, {"std", a.std}, {"min", a.min}, {"max", a.max}};
}

// Without RPE pairs its figures are null.
Json rpeJson(const EvalResult& r) {
  const bool have = r.rpe.pairs > 0;
  const auto v = [&](double x) { return have ? Json(x) : Json(nullptr); };
  const Stats& t = r.rpe.trans;
  const Stats& d = r.rpe.rot_deg;
  return {{"pairs", r.rpe.pairs},           {"delta_s", r.rpe.delta_s},       {"trans_rmse", v(t.rmse)},
          {"trans_mean", v(t.mean)},        {"trans_median", v(t.median)},    {"trans_std", v(t.std)},
          {"trans_min", v(t.min)},          {"trans_max", v(t.max)},          {"rot_rmse_deg", v(d.rmse)},
          {"rot_mean_deg", v(d.mean)},      {"rot_median_deg", v(d.median)}, {"rot_std_deg", v(d.std)},
          {"rot_min_deg", v(d.min)},        {"rot_max_deg", v(d.max)}};
}

}  // namespace

std::string toJson(const EvalResult& r) {
  const Eigen::Vector3d t = r.ate.T_gt_est.translation();
  const Eigen::Quaterniond q = r.ate.T_gt_est.quaternion();
  Json ate = figuresJson(r.ate.stats);
  ate["T_gt_est"] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
  const Json j = {{"pairs", r.ate.pairs.size()}, {"gt_file", r.gt_name},     {"est_file", r.est_name},
                  {"gt_poses", r.gt_poses},        {"est_poses", r.est_poses}, {"ate", ate},
                  {"rpe", rpeJson(r)}};
  return jsonText(j);
}

std::string toText(const EvalResult& r) {
  char buf[512];
  std::ostringstream os;
  os << "ground truth: " << r.gt_name << " (" << r.gt_poses << " poses)\n"
     << "estimate:     " << r.est_name << " (" << r.est_poses << " poses)\n"
     << "associated pairs: " << r.ate.pairs.size() << "\n";
  const Stats& a = r.ate.stats;
  std::snprintf(buf, sizeof(buf), "ATE (m):  rmse %.6f  mean %.6f  median %.6f  std %.6f  min %.6f  max %.6f\n", a.rmse,
                a.mean, a.median, a.std, a.min, a.max);
  os << buf;
  if (r.rpe.pairs > 0) {
    const Stats& t = r.rpe.trans;
    const Stats& d = r.rpe.rot_deg;
    std::snprintf(buf, sizeof(buf),
                  "RPE over %g s, %d pairs\n  trans (m):   rmse %.6f  mean %.6f  median %.6f  std %.6f  min %.6f  max %.6f\n"
                  "  rot (deg):   rmse %.6f  mean %.6f  median %.6f  std %.6f  min %.6f  max %.6f\n",
                  r.rpe.delta_s, r.rpe.pairs, t.rmse, t.mean, t.median, t.std, t.min, t.max, d.rmse, d.mean, d.median,
                  d.std, d.min, d.max);
    os << buf;
  } else {
    os << "RPE: no pair of poses " << r.rpe.delta_s << " s apart\n";
  }
  return os.str();
}

}  // namespace plslam
