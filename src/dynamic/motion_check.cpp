#include "dynamic/motion_check.h"

#include "core/rigid_fit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace plslam {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Projection Jacobian d(uv)/d(p) at camera-frame point q.
Eigen::Matrix<double, 2, 3> projectionJacobian(const PinholeCamera& cam, const Eigen::Vector3d& q) {
  const double iz = 1.0 / q.z();
  Eigen::Matrix<double, 2, 3> J;
  J << cam.fx * iz, 0, -cam.fx * q.x() * iz * iz, 0, cam.fy * iz, -cam.fy * q.y() * iz * iz;
  return J;
}

double chi2Of(const Eigen::Vector3d& r, const Eigen::Matrix3d& cov) { return r.dot(cov.ldlt().solve(r)); }

/// The depth correspondences with their covariances, precomputed once.
struct DepthSet {
  std::vector<int> index;  // into the correspondences
  std::vector<Eigen::Vector3d> p, c;
  std::vector<Eigen::Matrix3d> cov_p, cov_c;
  std::vector<Eigen::Matrix3d> info;  // (cov_p + cov_c)^-1: the hypothesis' rotation ignored (a few degrees between frames)
};

/// Exact chi2 of depth correspondence k under (R, t).
double setChi2(const DepthSet& s, size_t k, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  const Eigen::Vector3d r = R * s.p[k] + t - s.c[k];
  return chi2Of(r, R * s.cov_p[k] * R.transpose() + s.cov_c[k]);
}

/// The same with the precomputed information matrix (for scoring many hypotheses).
double fastChi2(const DepthSet& s, size_t k, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  const Eigen::Vector3d r = R * s.p[k] + t - s.c[k];
  return r.dot(s.info[k] * r);
}

// Hypotheses are ranked by a quantile (the median by default) of their chi2 values (LMedS),
// not by inlier counts or a truncated cost (MSAC): the depth noise model is only roughly
// right, and where it is too loose for the data, a motion that fits a near (precise) moving
// object also keeps the far (noisy) background within its threshold, out-counting and
// out-scoring the true motion. The median needs no noise scale: it picks the motion that fits
// the better half of the points best, i.e. the background as long as it holds the majority.
// The same quantile, compared with its value for chi2 with 3 dof, measures how much cleaner or
// noisier the data are than the model (the noise scale the thresholds are multiplied by).
struct Score {
  double value = kInf;  // the rank quantile of chi2 over the depth correspondences
  double scale = 1.0;   // noise scale: value / expected value, clamped
  int inliers = 0;      // chi2 below threshold * scale
  bool betterThan(const Score& o) const { return value < o.value || (value == o.value && inliers > o.inliers); }
};

/// The q-quantile of chi2 with 3 degrees of freedom (Wilson-Hilferty; the normal quantile by bisection).
double chi2Dof3Quantile(double q) {
  double lo = -8, hi = 8;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < q ? lo : hi) = mid;
  }
  const double z = 0.5 * (lo + hi), k = 3.0, a = 2.0 / (9.0 * k);
  return k * std::pow(std::max(0.0, 1.0 - a + z * std::sqrt(a)), 3);
}

struct Ranking {
  double quantile = 0.5;
  double expected = 2.366;  // chi2Dof3Quantile(quantile)
  double thr = 16.27;
  double min_scale = 1, max_scale = 1;
};

Score scoreMotion(const DepthSet& s, const SE3& T, const Ranking& rk, std::vector<double>& scratch) {
  const Eigen::Matrix3d R = T.rotation();
  Score sc;
  scratch.resize(s.p.size());
  for (size_t k = 0; k < s.p.size(); ++k) scratch[k] = fastChi2(s, k, R, T.translation());
  const size_t rank = std::min(scratch.size() - 1, static_cast<size_t>(rk.quantile * scratch.size()));
  std::nth_element(scratch.begin(), scratch.begin() + rank, scratch.end());
  sc.value = scratch[rank];
  sc.scale = std::clamp(sc.value / rk.expected, rk.min_scale, rk.max_scale);
  const double thr = rk.thr * sc.scale;
  for (double e : scratch) sc.inliers += e < thr;
  return sc;
}

/// Gauss-Newton on the Mahalanobis cost of the inliers of T (the full anisotropic covariances:
/// the lateral precision of far points counts, their depth noise does not swamp it).
SE3 refineMahalanobis(const DepthSet& s, SE3 T, double thr, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    const Eigen::Matrix3d R = T.rotation();
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    int used = 0;
    for (size_t k = 0; k < s.p.size(); ++k) {
      const Eigen::Vector3d q = R * s.p[k] + T.translation();
      const Eigen::Vector3d r = q - s.c[k];
      const Eigen::Matrix3d info = (R * s.cov_p[k] * R.transpose() + s.cov_c[k]).inverse();
      if (r.dot(info * r) >= thr) continue;
      Eigen::Matrix<double, 3, 6> J;
      J << Eigen::Matrix3d::Identity(), -hat(q);  // d(exp(d) * q) / d[rho; phi] at 0
      H += J.transpose() * info * J;
      g += J.transpose() * info * r;
      ++used;
    }
    if (used < 3) break;
    const Eigen::Matrix<double, 6, 1> step = H.ldlt().solve(-g);
    if (!step.allFinite()) break;
    T = SE3::exp(step) * T;
    if (step.norm() < 1e-9) break;
  }
  return T;
}

/// Weighted rigid refit on the inliers of T (weights: inverse positional variance).
std::optional<SE3> refitOnInliers(const DepthSet& s, const SE3& T, double thr) {
  const Eigen::Matrix3d R = T.rotation();
  std::vector<Eigen::Vector3d> a, b;
  std::vector<double> w;
  for (size_t k = 0; k < s.p.size(); ++k) {
    if (fastChi2(s, k, R, T.translation()) >= thr) continue;
    a.push_back(s.p[k]);
    b.push_back(s.c[k]);
    w.push_back(1.0 / (s.cov_p[k] + s.cov_c[k]).trace());
  }
  return fitUniqueRigid(a, b, w);
}

/// Whether T moves the scene's points (RMS) within the tolerance of where the prior moves them
/// (a distance on the scene, not at the camera centre: a rotation about a point 2 m away
/// looks like a large translation at the origin).
bool nearPrior(const DepthSet& s, const SE3& T, const SE3& prior, const MotionCheckOptions& o) {
  const Eigen::Matrix3d dR = T.rotation() - prior.rotation();
  const Eigen::Vector3d dt = T.translation() - prior.translation();
  const size_t stride = std::max<size_t>(1, s.p.size() / 64);  // a spread subset is enough
  const double limit = o.prior_max_displacement_m * o.prior_max_displacement_m;
  for (size_t k = 0; k < s.p.size(); k += stride)
    if ((dR * s.p[k] + dt).squaredNorm() > limit) return false;
  return true;
}

/// A minimal sample must be a proper triangle whose side lengths agree between the frames
/// (cheap rejection of samples that mix a moving object and the background).
enum class SampleCheck { kGood, kDegenerate, kNotRigid };

SampleCheck checkSample(const DepthSet& s, const int k[3], const MotionCheckOptions& o) {
  for (int a = 0; a < 3; ++a) {
    const int i = k[a], j = k[(a + 1) % 3], m = k[(a + 2) % 3];
    const Eigen::Vector3d e1 = s.p[j] - s.p[i], e2 = s.p[m] - s.p[i];
    const double l1 = e1.norm(), l2 = e2.norm();
    if (l1 < o.min_sample_side_m || l2 < o.min_sample_side_m) return SampleCheck::kDegenerate;
    if (e1.cross(e2).norm() / (l1 * l2) < o.min_sample_sine) return SampleCheck::kDegenerate;
  }
  const double gate = std::sqrt(o.chi2_1d);
  for (int a = 0; a < 3; ++a) {
    const int i = k[a], j = k[(a + 1) % 3];
    const double dl = std::abs((s.p[j] - s.p[i]).norm() - (s.c[j] - s.c[i]).norm());
    const double var = (s.cov_p[i] + s.cov_p[j] + s.cov_c[i] + s.cov_c[j]).trace();
    if (dl > gate * std::sqrt(var)) return SampleCheck::kNotRigid;
  }
  return SampleCheck::kGood;
}

}  // namespace

Eigen::Matrix3d pointCovariance(const PinholeCamera& camera, const Eigen::Vector2d& uv, double z,
                                const PointNoiseOptions& noise, double pixel_sigma_scale) {
  Eigen::Matrix3d J;
  J << z / camera.fx, 0, (uv.x() - camera.cx) / camera.fx, 0, z / camera.fy, (uv.y() - camera.cy) / camera.fy, 0, 0, 1;
  const double sp = noise.pixel_sigma * pixel_sigma_scale;
  const double sz = noise.depthSigma(z);
  const Eigen::Vector3d d(sp * sp, sp * sp, sz * sz);
  return J * d.asDiagonal() * J.transpose();
}

const char* motionCheckStatusName(MotionCheckStatus status) {
  switch (status) {
    case MotionCheckStatus::kOk: return "ok";
    case MotionCheckStatus::kTooFewCorrespondences: return "too_few_correspondences";
    case MotionCheckStatus::kTooFewWithDepth: return "too_few_with_depth";
    case MotionCheckStatus::kDegenerate: return "degenerate";
    case MotionCheckStatus::kNoConsensus: return "no_consensus";
  }
  return "unknown";
}

int MotionCheckResult::checkedCount() const {
  return static_cast<int>(std::count_if(evidence.begin(), evidence.end(), [](MotionEvidence e) { return e != MotionEvidence::kNone; }));
}

int MotionCheckResult::movingCount() const { return static_cast<int>(std::count(moving.begin(), moving.end(), 1)); }

namespace {

/// The correspondences with depth on both sides and finite pixels, with their covariances.
DepthSet buildDepthSet(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam,
                       const MotionCheckOptions& o) {
  DepthSet s;
  for (int i = 0; i < static_cast<int>(corr.size()); ++i) {
    const auto& c = corr[i];
    if (!c.hasDepthPrev() || !c.hasDepthCur() || !c.uv_prev.allFinite() || !c.uv_cur.allFinite()) continue;
    s.index.push_back(i);
    s.p.push_back(c.p_prev);
    s.c.push_back(c.p_cur);
    s.cov_p.push_back(pointCovariance(cam, c.uv_prev, c.p_prev.z(), o.noise, c.pixel_sigma_scale));
    s.cov_c.push_back(pointCovariance(cam, c.uv_cur, c.p_cur.z(), o.noise, c.pixel_sigma_scale));
    s.info.push_back((s.cov_p.back() + s.cov_c.back()).inverse());
  }
  return s;
}

Ranking makeRanking(const MotionCheckOptions& o, bool with_prior) {
  Ranking rk;
  rk.quantile = std::clamp(with_prior ? o.prior_rank_quantile : o.rank_quantile, 0.05, 0.95);
  rk.expected = chi2Dof3Quantile(rk.quantile);
  rk.thr = o.chi2_3d;
  if (o.adapt_noise_scale) {
    rk.min_scale = o.min_noise_scale;
    rk.max_scale = std::max(o.min_noise_scale, o.max_noise_scale);
  }
  return rk;
}

/// Three distinct indices below n.
void drawSample(std::mt19937_64& rng, int n, int k[3]) {
  k[0] = static_cast<int>(rng() % n);
  do k[1] = static_cast<int>(rng() % n); while (k[1] == k[0]);
  do k[2] = static_cast<int>(rng() % n); while (k[2] == k[0] || k[2] == k[1]);
}

/// RANSAC over minimal 3-point rigid fits (and the prior, when given), with local refits of
/// every new best hypothesis. Counts hypotheses and whether the prior won into the result.
class MotionSearch {
 public:
  MotionSearch(const DepthSet& s, const MotionCheckOptions& o, const std::optional<SE3>& prior, const Ranking& rk,
               MotionCheckResult* res)
      : s_(s), o_(o), prior_(prior), rk_(rk), res_(res), n_(static_cast<int>(s.p.size())),
        log_fail_(std::log(1.0 - std::clamp(o.confidence, 0.5, 1.0 - 1e-12))), needed_(o.max_iterations) {}

  void run() {
    std::mt19937_64 rng(o_.seed);
    if (prior_) consider(*prior_, true);
    const int max_draws = 20 * std::max(1, o_.max_iterations);
    for (int draw = 0, iter = 0; draw < max_draws && iter < std::min(needed_, o_.max_iterations); ++draw) {
      int k[3];
      drawSample(rng, n_, k);
      const SampleCheck check = checkSample(s_, k, o_);
      if (check == SampleCheck::kDegenerate) continue;
      ++good_samples;  // a proper triangle, rigid or not
      if (check == SampleCheck::kNotRigid) continue;
      const auto T = fitTriangleRigid({s_.p[k[0]], s_.p[k[1]], s_.p[k[2]]}, {s_.c[k[0]], s_.c[k[1]], s_.c[k[2]]});
      if (!T || (prior_ && !nearPrior(s_, *T, *prior_, o_))) continue;  // only hypotheses near the prior count
      ++iter;
      consider(*T, false);
    }
  }

  Score best;
  std::optional<SE3> best_T;
  int good_samples = 0;
  std::vector<double> scratch;

 private:
  void consider(const SE3& T, bool is_prior) {
    ++res_->hypotheses;
    Score sc = scoreMotion(s_, T, rk_, scratch);
    if (!sc.betterThan(best)) return;
    best = sc;
    best_T = T;
    res_->prior_won = is_prior;
    // Local optimisation: minimal samples of noisy far points give rough motions; refits on
    // their inliers make a near-true hypothesis score as well as it deserves.
    // (Inliers at most at the model's threshold: a poor hypothesis has a large noise scale.)
    for (int lo = 0; lo < o_.refine_iterations; ++lo) {
      const auto refit = refitOnInliers(s_, *best_T, rk_.thr * std::min(best.scale, 1.0));
      if (!refit || (prior_ && !nearPrior(s_, *refit, *prior_, o_))) break;
      sc = scoreMotion(s_, *refit, rk_, scratch);
      if (!sc.betterThan(best)) break;
      best = sc;
      best_T = refit;
      res_->prior_won = false;
    }
    const double w = static_cast<double>(best.inliers) / n_;
    const double p_fail = 1.0 - w * w * w;
    needed_ = p_fail <= 0 ? o_.min_iterations
                          : std::max(o_.min_iterations, static_cast<int>(std::ceil(log_fail_ / std::log(p_fail))));
  }

  const DepthSet& s_;
  const MotionCheckOptions& o_;
  const std::optional<SE3>& prior_;
  const Ranking& rk_;
  MotionCheckResult* res_;
  const int n_;
  const double log_fail_;
  int needed_;
};

/// Maximum-likelihood polish of T on the inliers, kept when it does not rank worse (updates `best`).
SE3 polishMotion(const DepthSet& s, SE3 T, const std::optional<SE3>& prior, const MotionCheckOptions& o,
                 const Ranking& rk, Score* best, std::vector<double>& scratch) {
  for (int round = 0; round < 2; ++round) {
    const SE3 polished = refineMahalanobis(s, T, rk.thr * best->scale, o.refine_iterations + 2);
    if (prior && !nearPrior(s, polished, *prior, o)) break;
    const Score sc = scoreMotion(s, polished, rk, scratch);
    if (sc.value > best->value * 1.05) break;
    T = polished;
    *best = sc;
  }
  return T;
}

/// The tests of single correspondences against the camera motion T (cur <- prev).
class MotionTests {
 public:
  MotionTests(const PinholeCamera& cam, const MotionCheckOptions& o, const SE3& T, double noise_scale)
      : cam_(cam), o_(o), T_(T), R_(T.rotation()), t_(T.translation()), T_prev_cur_(T.inverse()),
        noise_scale_(noise_scale) {
    Eigen::Matrix3d Kinv;
    Kinv << 1 / cam.fx, 0, -cam.cx / cam.fx, 0, 1 / cam.fy, -cam.cy / cam.fy, 0, 0, 1;
    F_ = Kinv.transpose() * hat(t_) * R_ * Kinv;  // x_cur^T F x_prev = 0
    f_ = std::max(std::abs(cam.fx), std::abs(cam.fy));  // pixels per unit of x/z; fx, fy are signed
  }

  /// Every depth correspondence by its 3D residual (exact covariances); recounts the inliers.
  void rigid3d(const DepthSet& s, MotionCheckResult& res) const {
    const int n = static_cast<int>(s.p.size());
    for (int k = 0; k < n; ++k) {
      const int i = s.index[k];
      res.evidence[i] = MotionEvidence::kRigid3d;
      res.chi2[i] = setChi2(s, k, R_, t_);
      res.residual[i] = (R_ * s.p[k] + t_ - s.c[k]).norm();
      res.moving[i] = res.chi2[i] >= o_.chi2_3d * noise_scale_;
    }
    res.inliers = 0;  // with the exact covariances (scoring used the unrotated ones)
    for (int k = 0; k < n; ++k) res.inliers += !res.moving[s.index[k]];
  }

  /// A correspondence without depth on both sides, by the best test its data allow.
  void single(const MotionCorrespondence& c, int i, MotionCheckResult& res) const {
    if (res.evidence[i] != MotionEvidence::kNone || !c.uv_prev.allFinite() || !c.uv_cur.allFinite()) return;
    const double sp = o_.noise.pixel_sigma * c.pixel_sigma_scale;
    if (c.hasDepthPrev() || c.hasDepthCur())
      reprojection(c, i, sp, res);
    else if (t_.norm() >= o_.min_epipolar_baseline_m)
      epipolar(c, i, sp, res);
    else
      rotationOnly(c, i, sp, res);
  }

 private:
  /// Reprojection of the side with depth into the other image.
  void reprojection(const MotionCorrespondence& c, int i, double sp, MotionCheckResult& res) const {
    const bool from_prev = c.hasDepthPrev();
    const Eigen::Vector3d q = from_prev ? T_ * c.p_prev : T_prev_cur_ * c.p_cur;
    const Eigen::Vector2d uv_obs = from_prev ? c.uv_cur : c.uv_prev;
    res.evidence[i] = MotionEvidence::kReprojection;
    if (q.z() <= 1e-6) {  // lands behind the camera
      res.residual[i] = res.chi2[i] = kInf;
      res.moving[i] = 1;
      return;
    }
    const Eigen::Matrix3d Rq = from_prev ? R_ : Eigen::Matrix3d(R_.transpose());
    const Eigen::Matrix3d cov3 = from_prev ? pointCovariance(cam_, c.uv_prev, c.p_prev.z(), o_.noise, c.pixel_sigma_scale)
                                           : pointCovariance(cam_, c.uv_cur, c.p_cur.z(), o_.noise, c.pixel_sigma_scale);
    const auto J = projectionJacobian(cam_, q);
    const Eigen::Matrix2d cov = J * Rq * cov3 * Rq.transpose() * J.transpose() + sp * sp * Eigen::Matrix2d::Identity();
    const Eigen::Vector2d e = uv_obs - cam_.projectIdeal(q);
    res.residual[i] = e.norm();
    res.chi2[i] = e.dot(cov.ldlt().solve(e));
    res.moving[i] = res.chi2[i] >= o_.chi2_2d * noise_scale_;
  }

  void epipolar(const MotionCorrespondence& c, int i, double sp, MotionCheckResult& res) const {
    const Eigen::Vector3d line = F_ * Eigen::Vector3d(c.uv_prev.x(), c.uv_prev.y(), 1.0);
    const double d = std::abs(line.dot(Eigen::Vector3d(c.uv_cur.x(), c.uv_cur.y(), 1.0))) / line.head<2>().norm();
    res.evidence[i] = MotionEvidence::kEpipolar;
    res.residual[i] = d;
    res.chi2[i] = d * d / (2 * sp * sp);
    res.moving[i] = res.chi2[i] >= o_.chi2_1d * noise_scale_;
  }

  /// Hardly any translation: the rotation alone predicts the pixel, up to the parallax
  /// of the nearest plausible depth.
  void rotationOnly(const MotionCorrespondence& c, int i, double sp, MotionCheckResult& res) const {
    const Eigen::Vector3d ray = R_ * cam_.unprojectIdeal(c.uv_prev, 1.0);
    if (ray.z() <= 1e-6) return;  // rotated out of view: no check
    res.evidence[i] = MotionEvidence::kRotation;
    const double e = (c.uv_cur - cam_.projectIdeal(ray)).norm();
    const double excess = std::max(0.0, e - f_ * t_.norm() / o_.min_scene_depth_m);
    res.residual[i] = e;
    res.chi2[i] = excess * excess / (2 * sp * sp);
    res.moving[i] = res.chi2[i] >= o_.chi2_2d * noise_scale_;
  }

  const PinholeCamera& cam_;
  const MotionCheckOptions& o_;
  const SE3 T_;
  const Eigen::Matrix3d R_;
  const Eigen::Vector3d t_;
  const SE3 T_prev_cur_;
  const double noise_scale_;
  Eigen::Matrix3d F_;
  double f_;
};

/// A result for n correspondences, none checked yet.
MotionCheckResult uncheckedResult(size_t n) {
  MotionCheckResult res;
  res.moving.assign(n, 0);
  res.evidence.assign(n, MotionEvidence::kNone);
  res.residual.assign(n, kNaN);
  res.chi2.assign(n, kNaN);
  return res;
}

/// Checks every correspondence against the camera motion of `tests`.
void judgeAll(const std::vector<MotionCorrespondence>& corr, const DepthSet& s, const MotionTests& tests,
              MotionCheckResult& res) {
  tests.rigid3d(s, res);
  for (int i = 0; i < static_cast<int>(corr.size()); ++i) tests.single(corr[i], i, res);
}

MotionCheckResult checkMotionOnce(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam,
                                  const MotionCheckOptions& o, const std::optional<SE3>& prior) {
  const int n_all = static_cast<int>(corr.size());
  MotionCheckResult res = uncheckedResult(corr.size());
  res.prior_used = prior.has_value();

  const DepthSet s = buildDepthSet(corr, cam, o);
  const int n = static_cast<int>(s.p.size());
  res.with_depth = n;
  if (n_all < o.min_correspondences) {
    res.status = MotionCheckStatus::kTooFewCorrespondences;
    return res;
  }
  if (n < std::max(3, o.min_with_depth)) {
    res.status = MotionCheckStatus::kTooFewWithDepth;
    return res;
  }

  const Ranking rk = makeRanking(o, prior.has_value());
  MotionSearch search(s, o, prior, rk, &res);
  search.run();
  Score best = search.best;
  if (!search.best_T) {
    res.status = search.good_samples == 0 && !prior ? MotionCheckStatus::kDegenerate : MotionCheckStatus::kNoConsensus;
    return res;
  }
  if (best.inliers >= 3 && !refitOnInliers(s, *search.best_T, rk.thr * best.scale)) {
    res.status = MotionCheckStatus::kDegenerate;  // the inliers are collinear
    return res;
  }

  const SE3 T = polishMotion(s, *search.best_T, prior, o, rk, &best, search.scratch);
  const int count = best.inliers;
  res.noise_scale = best.scale;
  res.inliers = count;
  if (count < std::max(3, o.min_inliers) || count < o.min_inlier_ratio * n) {
    res.status = MotionCheckStatus::kNoConsensus;
    return res;
  }
  res.status = MotionCheckStatus::kOk;
  res.T_cur_prev = T;

  judgeAll(corr, s, MotionTests(cam, o, T, res.noise_scale), res);
  return res;
}

}  // namespace

MotionCheckResult checkMotion(const std::vector<MotionCorrespondence>& correspondences, const PinholeCamera& camera,
                              const MotionCheckOptions& options, const std::optional<SE3>& prior) {
  MotionCheckResult res = checkMotionOnce(correspondences, camera, options, prior);
  if (prior && res.status == MotionCheckStatus::kNoConsensus) {
    if (options.prior_fallback) res = checkMotionOnce(correspondences, camera, options, std::nullopt);
    res.prior_rejected = true;
  }
  return res;
}

MotionCheckResult judgeAgainstMotion(const std::vector<MotionCorrespondence>& correspondences,
                                     const PinholeCamera& camera, const MotionCheckOptions& options,
                                     const SE3& T_cur_prev, double noise_scale) {
  MotionCheckResult res = uncheckedResult(correspondences.size());
  const DepthSet s = buildDepthSet(correspondences, camera, options);
  res.with_depth = static_cast<int>(s.p.size());
  res.status = MotionCheckStatus::kOk;
  res.T_cur_prev = T_cur_prev;
  res.noise_scale = noise_scale;
  judgeAll(correspondences, s, MotionTests(camera, options, T_cur_prev, noise_scale), res);
  return res;
}

}  // namespace plslam
