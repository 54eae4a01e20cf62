#include "mapping/line_reconstruction.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "core/map.h"
#include "core/option_table.h"

namespace plslam {

const char* toString(LineFitStatus status) {
  switch (status) {
    case LineFitStatus::kOk: return "ok";
    case LineFitStatus::kSegmentTooShort: return "segment too short";
    case LineFitStatus::kTooFewDepthSamples: return "too few depth samples";
    case LineFitStatus::kTooFewInliers: return "too few inliers";
    case LineFitStatus::kDegenerateViewingRay: return "line along the viewing ray";
    case LineFitStatus::kImplausibleLength: return "implausible 3D length";
    case LineFitStatus::kEndpointDepthMissing: return "endpoint depth missing";
    case LineFitStatus::kMidpointDepthMismatch: return "midpoint depth mismatch";
  }
  return "unknown";
}

void bindLineFitOptions(OptionTable* t, const std::string& p, LineFitOptions* o) {
  t->bind(p + "sample_step_px", &o->sample_step_px, "spacing of depth samples along a segment (px)", above(0));
  t->bind(p + "max_samples", &o->max_samples, "depth samples per segment at most (the spacing grows)", atLeast(2));
  t->bind(p + "min_segment_px", &o->min_segment_px, "shorter segments get no 3D line (px)", atLeast(0));
  t->bind(p + "min_depth_m", &o->min_depth_m, "depth samples nearer than this count as missing (m)", above(0));
  t->bind(p + "max_depth_m", &o->max_depth_m, "depth samples beyond this count as missing (m)", above(0));
  t->bind(p + "perp_search_px", &o->perp_search_px, "half-width of the depth window across the segment (px)", within(0, 10));
  t->bind(p + "surface_jump_tolerances", &o->surface_jump_tolerances,
          "a step above this many inlier tolerances between window neighbours separates two surfaces", atLeast(1));
  t->bind(p + "depth_noise_coeff", &o->depth_noise_coeff, "inlier tolerance: depth sigma = coeff * z^2 (1/m)", atLeast(0));
  t->bind(p + "inlier_sigmas", &o->inlier_sigmas, "inlier tolerance in depth sigmas", atLeast(0));
  t->bind(p + "inlier_base_m", &o->inlier_base_m, "constant part of the inlier tolerance (m)", above(0));
  t->bind(p + "min_inlier_ratio", &o->min_inlier_ratio, "fraction of the samples with depth a fitted 3D line must explain", within(0, 1));
  t->bind(p + "min_inliers", &o->min_inliers, "and at least this many inlier samples", atLeast(2));
  t->bind(p + "refit_iterations", &o->refit_iterations, "inlier re-selections and refits after RANSAC", atLeast(0));
  t->bind(p + "max_extrapolation", &o->max_extrapolation, "endpoints may reach past the outermost inliers by this fraction of their extent", atLeast(0));
  t->bind(p + "min_view_angle_deg", &o->min_view_angle_deg, "lines closer than this to an endpoint's viewing ray are refused (deg)", Range{0, 90, false});
  t->bind(p + "min_length_m", &o->min_length_m, "shortest 3D segment kept (m)", atLeast(0));
  t->bind(p + "max_length_m", &o->max_length_m, "longest 3D segment kept (m)", above(0));
  t->bind(p + "endpoint_median3x3", &o->endpoint_median3x3, "endpoint method (its rate is reported): depth = median of the valid 3x3 neighbours (5 needed), else the exact pixel");
}

void LineFitOptions::validate() const {
  auto fail = [](const std::string& what) { throw ConfigError("line fit options: " + what); };
  if (!(sample_step_px > 0)) fail(str("sample_step_px ", sample_step_px, " must be positive"));
  if (max_samples < 2) fail(str("max_samples ", max_samples, " must be at least 2"));
  if (!(min_segment_px >= 0)) fail(str("min_segment_px ", min_segment_px, " must be >= 0"));
  if (!(min_depth_m > 0) || !(max_depth_m > min_depth_m))
    fail(str("depth range [", min_depth_m, ", ", max_depth_m, "] must satisfy 0 < min < max"));
  if (!(surface_jump_tolerances >= 1)) fail(str("surface_jump_tolerances ", surface_jump_tolerances, " must be >= 1"));
  if (perp_search_px < 0 || perp_search_px > 10) fail(str("perp_search_px ", perp_search_px, " must be in 0..10"));
  if (!(depth_noise_coeff >= 0) || !(inlier_sigmas >= 0) || !(inlier_base_m > 0))
    fail("depth_noise_coeff and inlier_sigmas must be >= 0 and inlier_base_m > 0");
  if (!(min_inlier_ratio >= 0 && min_inlier_ratio <= 1)) fail(str("min_inlier_ratio ", min_inlier_ratio, " must be in [0, 1]"));
  if (min_inliers < 2) fail(str("min_inliers ", min_inliers, " must be at least 2"));
  if (refit_iterations < 0) fail(str("refit_iterations ", refit_iterations, " must be >= 0"));
  if (!(max_extrapolation >= 0)) fail(str("max_extrapolation ", max_extrapolation, " must be >= 0"));
  if (!(min_view_angle_deg >= 0 && min_view_angle_deg < 90))
    fail(str("min_view_angle_deg ", min_view_angle_deg, " must be in [0, 90)"));
  if (!(min_length_m >= 0) || !(max_length_m > min_length_m))
    fail(str("length range [", min_length_m, ", ", max_length_m, "] must satisfy 0 <= min < max"));
}

void LineReconstructionRate::add(int built, int used) {
  if (built < 0 || used < 0 || built > used)
    throw DataError(str("line reconstruction rate: built ", built, " and used ", used, " must satisfy 0 <= built <= used"));
  built_ += built;
  used_ += used;
  if (used == 0) return;
  sum_rates_ += static_cast<double>(built) / used;
  ++frames_;
}

namespace {

bool inRange(float z, const LineFitOptions& o) { return std::isfinite(z) && z >= o.min_depth_m && z <= o.max_depth_m; }

void checkDepthImage(const cv::Mat& depth_m, const char* who) {
  if (depth_m.empty() || depth_m.type() != CV_32FC1)
    throw DataError(str(who, ": the depth image must be a non-empty CV_32FC1 image in metres"));
}

/// Viewing ray (z = 1) through an ideal pixel.
Eigen::Vector3d rayIdeal(const PinholeCamera& cam, const Eigen::Vector2d& uv) {
  return {(uv.x() - cam.cx) / cam.fx, (uv.y() - cam.cy) / cam.fy, 1.0};
}

/// Sine of the angle between a unit direction and a (not normalised) ray.
double sinAngle(const Eigen::Vector3d& dir_unit, const Eigen::Vector3d& ray) {
  return dir_unit.cross(ray).norm() / ray.norm();
}

/// Depth for a sample on the segment, from the pixels of a window perpendicular to it.
/// Only the NEAR surface counts: the run of window pixels connected to the nearest one
/// without a depth step larger than surface_jump_tolerances * tolerance (an occluding edge
/// belongs to the near surface; a surface seen obliquely may still change a lot across the
/// window, and a generous step keeps noise from cutting its highest pixels off, which would
/// bias the depth towards the camera). Inverse
/// depth, affine in the image across a plane, is then interpolated at the segment between
/// the run's nearest pixels on either side of it, or, when the run lies on one side only (a
/// silhouette), extrapolated by a least-squares affine fit over the run (change limited to
/// the tolerance). NaN when the window holds no valid depth.
float sampleDepth(const cv::Mat& depth_m, const Eigen::Vector2d& uv, const Eigen::Vector2d& perp,
                  const LineFitOptions& o) {
  struct Px {
    double s;  // signed distance of the pixel centre from the segment, pixels
    double z;
  };
  const int r = std::clamp(o.perp_search_px, 0, 10);
  std::array<Px, 21> window;  // ordered by s
  int m = 0, imin = -1;
  for (int k = -r; k <= r; ++k) {
    const Eigen::Vector2d w = uv + k * perp;
    const Eigen::Vector2d centre(std::round(w.x()), std::round(w.y()));
    const float z = depthAt(depth_m, centre.x(), centre.y());
    if (!inRange(z, o)) continue;
    window[m] = {(centre - uv).dot(perp), z};
    if (imin < 0 || z < window[imin].z) imin = m;
    ++m;
  }
  if (m == 0) return std::nanf("");
  int lo = imin, hi = imin;  // the near-surface run [lo, hi]
  const double jump = o.surface_jump_tolerances;
  while (lo > 0 && std::abs(window[lo - 1].z - window[lo].z) <= jump * o.tolerance(window[lo].z)) --lo;
  while (hi + 1 < m && std::abs(window[hi + 1].z - window[hi].z) <= jump * o.tolerance(window[hi].z)) ++hi;

  // Straddling the segment: interpolate between the nearest pixels on either side.
  for (int i = lo; i < hi; ++i) {
    const Px& a = window[i];
    const Px& b = window[i + 1];
    if (a.s <= 0 && b.s >= 0) {
      if (b.s - a.s < 1e-9) return static_cast<float>(a.z);
      const double w = b.s / (b.s - a.s);
      return static_cast<float>(1.0 / (w / a.z + (1 - w) / b.z));
    }
  }
  // One-sided: least-squares affine fit of inverse depth over the run, evaluated at s = 0.
  const Px& nearest = std::abs(window[lo].s) < std::abs(window[hi].s) ? window[lo] : window[hi];
  if (hi == lo) return static_cast<float>(nearest.z);
  double n = 0, ss = 0, si = 0, sss = 0, ssi = 0;
  for (int i = lo; i <= hi; ++i) {
    const double inv = 1.0 / window[i].z;
    n += 1;
    ss += window[i].s;
    si += inv;
    sss += window[i].s * window[i].s;
    ssi += window[i].s * inv;
  }
  const double det = n * sss - ss * ss;
  if (det < 1e-9) return static_cast<float>(nearest.z);
  const double inv0 = (sss * si - ss * ssi) / det;  // intercept
  const double t = o.tolerance(nearest.z);
  const double z = inv0 > 0 ? 1.0 / inv0 : nearest.z + t;
  return static_cast<float>(std::clamp(z, nearest.z - t, nearest.z + t));
}

struct Line3 {
  Eigen::Vector3d c;  ///< a point on the line
  Eigen::Vector3d d;  ///< unit direction
  double distance(const Eigen::Vector3d& x) const { return (x - c).cross(d).norm(); }
};

/// Weighted PCA line through the selected points.
Line3 fitPca(const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& w, const std::vector<int>& idx) {
  double wsum = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int i : idx) {
    c += w[i] * pts[i];
    wsum += w[i];
  }
  c /= wsum;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i : idx) {
    const Eigen::Vector3d e = pts[i] - c;
    cov += w[i] * e * e.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  return {c, es.eigenvectors().col(2).normalized()};  // eigenvalues ascending
}

/// Parameter s of the point of `line` closest to the ray t * ray (through the camera centre).
double closestOnLineToRay(const Line3& line, const Eigen::Vector3d& ray) {
  // Lines c + s d and 0 + t r: s = (b e - c d) / (a c - b^2) with a = d.d = 1.
  const double b = line.d.dot(ray), cc = ray.dot(ray), dd = line.d.dot(line.c), e = ray.dot(line.c);
  const double denom = cc - b * b;
  return (b * e - cc * dd) / denom;
}

std::nullopt_t reject(LineFitDiagnostics* diag, LineFitStatus status) {
  if (diag) diag->status = status;
  return std::nullopt;
}

/// Checks shared by both methods: 3D length, then the viewing angle at both endpoints.
LineFitStatus plausibility(const Eigen::Vector3d& P, const Eigen::Vector3d& Q, const LineFitOptions& o) {
  const double len = (Q - P).norm();
  if (!(len >= o.min_length_m && len <= o.max_length_m)) return LineFitStatus::kImplausibleLength;
  const Eigen::Vector3d d = (Q - P) / len;
  const double min_sin = std::sin(o.min_view_angle_deg * M_PI / 180.0);
  if (P.z() <= 0 || Q.z() <= 0 || sinAngle(d, P) < min_sin || sinAngle(d, Q) < min_sin)
    return LineFitStatus::kDegenerateViewingRay;
  return LineFitStatus::kOk;
}

/// 3D points along a segment with their inlier tolerances and PCA weights (1 / tolerance^2).
struct DepthSamples {
  int n = 0;  ///< samples tried
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> tol, weight;
  int valid() const { return static_cast<int>(pts.size()); }

  /// The inliers of `line` (distance within the tolerance) and the truncated cost.
  void inliersOf(const Line3& line, std::vector<int>* idx, double* cost) const {
    idx->clear();
    *cost = 0;
    for (int i = 0; i < valid(); ++i) {
      const double dist = line.distance(pts[i]);
      if (dist <= tol[i]) {
        idx->push_back(i);
        *cost += dist / tol[i];
      } else {
        *cost += 1.0;
      }
    }
  }
};

/// 1-2. Samples along the ideal segment p-q, depth looked up at the raw pixel.
DepthSamples sampleSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& p_raw,
                           const Eigen::Vector2d& q_raw, double len_px, const cv::Mat& depth_m,
                           const PinholeCamera& cam, const LineFitOptions& o) {
  DepthSamples smp;
  const int n = std::clamp(static_cast<int>(len_px / o.sample_step_px) + 1, 2, o.max_samples);
  smp.n = n;
  Eigen::Vector2d perp(-(q_raw - p_raw).y(), (q_raw - p_raw).x());
  if (perp.norm() > 0) perp.normalize();
  smp.pts.reserve(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d uv = p + (q - p) * (static_cast<double>(i) / (n - 1));
    const float z = sampleDepth(depth_m, cam.distort(uv), perp, o);
    if (!std::isfinite(z)) continue;
    smp.pts.push_back(cam.unprojectIdeal(uv, z));
    smp.tol.push_back(o.tolerance(z));
    smp.weight.push_back(1.0 / (smp.tol.back() * smp.tol.back()));
  }
  return smp;
}

/// 3. Exhaustive RANSAC over well-separated pairs: most inliers, then lowest truncated cost.
/// Returns the best inlier count (-1: no pair).
int ransacLine(const DepthSamples& smp, Line3* best) {
  const std::vector<Eigen::Vector3d>& pts = smp.pts;
  const int nv = smp.valid();
  const int min_gap = std::max(1, nv / 3);
  *best = Line3{pts[0], Eigen::Vector3d::UnitZ()};
  int best_count = -1;
  double best_cost = 0;
  std::vector<int> idx;
  for (int i = 0; i < nv && best_count < nv; ++i) {
    for (int j = i + min_gap; j < nv; ++j) {
      const Eigen::Vector3d d = pts[j] - pts[i];
      if (d.norm() < 1e-6) continue;
      const Line3 cand{pts[i], d.normalized()};
      double cost;
      smp.inliersOf(cand, &idx, &cost);
      const int count = static_cast<int>(idx.size());
      if (count > best_count || (count == best_count && cost < best_cost)) {
        *best = cand;
        best_count = count;
        best_cost = cost;
        if (best_count == nv) break;
      }
    }
  }
  return best_count;
}

/// 4. Weighted PCA refits with inlier re-selection; `idx` ends as the final inlier set.
Line3 refitLine(const DepthSamples& smp, const Line3& start, int needed, int refit_iterations, std::vector<int>* idx) {
  double cost;
  smp.inliersOf(start, idx, &cost);
  Line3 line = fitPca(smp.pts, smp.weight, *idx);
  for (int it = 0; it < refit_iterations; ++it) {
    std::vector<int> next;
    smp.inliersOf(line, &next, &cost);
    if (static_cast<int>(next.size()) < needed) break;  // keep the previous inlier set
    const bool same = next == *idx;
    *idx = std::move(next);
    line = fitPca(smp.pts, smp.weight, *idx);
    if (same) break;
  }
  return line;
}

/// The inliers' extent along the line (parameters s_lo..s_hi) and RMS distance from it.
struct InlierExtent {
  double s_lo = 0, s_hi = 0, rms = 0;
};

InlierExtent inlierExtent(const DepthSamples& smp, const Line3& line, const std::vector<int>& idx) {
  const int count = static_cast<int>(idx.size());
  double s_lo = std::numeric_limits<double>::infinity(), s_hi = -s_lo, sq = 0;
  for (int i : idx) {
    const double s = (smp.pts[i] - line.c).dot(line.d);
    s_lo = std::min(s_lo, s);
    s_hi = std::max(s_hi, s);
    sq += std::pow(line.distance(smp.pts[i]), 2);
  }
  return {s_lo, s_hi, std::sqrt(sq / std::max(count, 1))};
}

}  // namespace

std::optional<LineSegment3D> fitLine3D(const Eigen::Vector2d& p_raw, const Eigen::Vector2d& q_raw,
                                       const cv::Mat& depth_m, const PinholeCamera& cam,
                                       const LineFitOptions& o, LineFitDiagnostics* diag) {
  checkDepthImage(depth_m, "fitLine3D");
  if (diag) *diag = LineFitDiagnostics{};
  const Eigen::Vector2d p = cam.undistort(p_raw), q = cam.undistort(q_raw);
  const double len_px = (q - p).norm();
  if (!(len_px >= o.min_segment_px) || len_px <= 0) return reject(diag, LineFitStatus::kSegmentTooShort);

  const DepthSamples smp = sampleSegment(p, q, p_raw, q_raw, len_px, depth_m, cam, o);
  const int nv = smp.valid();
  if (diag) {
    diag->samples = smp.n;
    diag->valid_samples = nv;
  }
  if (nv < std::max(o.min_inliers, 2)) return reject(diag, LineFitStatus::kTooFewDepthSamples);
  const int needed = std::max(o.min_inliers, static_cast<int>(std::ceil(o.min_inlier_ratio * nv - 1e-9)));

  Line3 best;
  const int best_count = ransacLine(smp, &best);
  if (best_count < needed) {
    if (diag) diag->inliers = std::max(best_count, 0);
    return reject(diag, LineFitStatus::kTooFewInliers);
  }

  std::vector<int> idx;
  const Line3 line = refitLine(smp, best, needed, o.refit_iterations, &idx);
  const int count = static_cast<int>(idx.size());
  const InlierExtent ext = inlierExtent(smp, line, idx);
  if (diag) {
    diag->inliers = count;
    diag->rms_m = ext.rms;
  }
  if (count < needed) return reject(diag, LineFitStatus::kTooFewInliers);

  // 5. Endpoints from the viewing rays through p and q, clamped to the (widened) inlier extent.
  const Eigen::Vector3d ray_p = rayIdeal(cam, p), ray_q = rayIdeal(cam, q);
  const double min_sin = std::sin(o.min_view_angle_deg * M_PI / 180.0);
  if (sinAngle(line.d, ray_p) < min_sin || sinAngle(line.d, ray_q) < min_sin)
    return reject(diag, LineFitStatus::kDegenerateViewingRay);
  const double margin = o.max_extrapolation * (ext.s_hi - ext.s_lo);
  const double sp = std::clamp(closestOnLineToRay(line, ray_p), ext.s_lo - margin, ext.s_hi + margin);
  const double sq_end = std::clamp(closestOnLineToRay(line, ray_q), ext.s_lo - margin, ext.s_hi + margin);

  LineSegment3D seg;
  seg.P_c = line.c + sp * line.d;
  seg.Q_c = line.c + sq_end * line.d;
  seg.inliers = count;
  seg.rms_m = ext.rms;
  if (const LineFitStatus st = plausibility(seg.P_c, seg.Q_c, o); st != LineFitStatus::kOk) return reject(diag, st);
  return seg;
}

namespace {

/// Endpoint-method depth: 3x3 median of the valid in-range pixels (at least 5 of them) or
/// the exact pixel. NaN when missing.
float endpointDepth(const cv::Mat& depth_m, const Eigen::Vector2d& uv, const LineFitOptions& o) {
  if (!o.endpoint_median3x3) {
    const float z = depthAt(depth_m, uv.x(), uv.y());
    return inRange(z, o) ? z : std::nanf("");
  }
  std::array<float, 9> v;
  int m = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float z = depthAt(depth_m, uv.x() + dx, uv.y() + dy);
      if (inRange(z, o)) v[m++] = z;
    }
  if (m < 5) return std::nanf("");
  std::nth_element(v.begin(), v.begin() + m / 2, v.begin() + m);
  return v[m / 2];
}

}  // namespace

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segmentsFittedToDepth(const std::vector<Segment2D>& segments,
                                                                                const cv::Mat& depth_m,
                                                                                const PinholeCamera& cam) {
  const Eigen::Vector3d nan = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  out.reserve(segments.size());
  for (const Segment2D& l : segments) {
    const std::optional<LineSegment3D> s =
        depth_m.empty() ? std::nullopt : fitLine3D(l.p_raw, l.q_raw, depth_m, cam, LineFitOptions{});
    out.emplace_back(s ? s->P_c : nan, s ? s->Q_c : nan);
  }
  return out;
}

std::optional<LineSegment3D> backprojectEndpoints(const Eigen::Vector2d& p_raw, const Eigen::Vector2d& q_raw,
                                                  const cv::Mat& depth_m, const PinholeCamera& cam,
                                                  const LineFitOptions& o, LineFitDiagnostics* diag) {
  checkDepthImage(depth_m, "backprojectEndpoints");
  if (diag) *diag = LineFitDiagnostics{};
  const double len_px = (cam.undistort(q_raw) - cam.undistort(p_raw)).norm();
  if (!(len_px >= o.min_segment_px) || len_px <= 0) return reject(diag, LineFitStatus::kSegmentTooShort);
  const float zp = endpointDepth(depth_m, p_raw, o), zq = endpointDepth(depth_m, q_raw, o);
  if (diag) {
    diag->samples = 2;
    diag->valid_samples = std::isfinite(zp) + std::isfinite(zq);
  }
  if (!std::isfinite(zp) || !std::isfinite(zq)) return reject(diag, LineFitStatus::kEndpointDepthMissing);

  LineSegment3D seg;
  seg.P_c = cam.unproject(p_raw, zp);
  seg.Q_c = cam.unproject(q_raw, zq);
  const Eigen::Vector3d mid = 0.5 * (seg.P_c + seg.Q_c);
  const float zm = endpointDepth(depth_m, cam.project(mid), o);
  if (!std::isfinite(zm) || std::abs(mid.z() - zm) > o.tolerance(zm))
    return reject(diag, LineFitStatus::kMidpointDepthMismatch);
  seg.inliers = 3;
  seg.rms_m = std::abs(mid.z() - zm);
  if (diag) {
    diag->inliers = 3;
    diag->rms_m = seg.rms_m;
  }
  if (const LineFitStatus st = plausibility(seg.P_c, seg.Q_c, o); st != LineFitStatus::kOk) return reject(diag, st);
  return seg;
}

}  // namespace plslam
