#include "features/line_extractor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/fast_line_detector.hpp>

#include "core/error.h"
#include "core/log.h"
#include "features/lbd.h"
#include "features/lsd.h"
#include "features/orb_extractor.h"

namespace plslam {

void LineOptions::validate() const {
  auto fail = [](const std::string& m) { throw ConfigError("features.lines: " + m); };
  if (detector != "lsd" && detector != "fld") fail("detector '" + detector + "' must be lsd or fld");
  if (fld_min_length_px < 1 || fld_min_length_px > 10000) fail(str("fld_min_length_px ", fld_min_length_px, " must be in 1..10000"));
  if (!(fld_canny_low >= 0 && fld_canny_high >= fld_canny_low && fld_canny_high <= 1000))
    fail(str("fld_canny_low ", fld_canny_low, " and fld_canny_high ", fld_canny_high, " must satisfy 0 <= low <= high <= 1000"));
  if (!(detect_scale > 0 && detect_scale <= 1)) fail(str("detect_scale ", detect_scale, " must be in (0, 1]"));
  if (!(lsd_quant > 0 && lsd_quant <= 50)) fail(str("lsd_quant ", lsd_quant, " must be in (0, 50]"));
  if (!(merge_angle_deg >= 0 && merge_angle_deg < 45)) fail(str("merge_angle_deg ", merge_angle_deg, " must be in [0, 45)"));
  if (!(merge_distance_px >= 0 && merge_distance_px <= 50))
    fail(str("merge_distance_px ", merge_distance_px, " must be in [0, 50]"));
  if (!(merge_gap_px >= 0 && merge_gap_px <= 1000)) fail(str("merge_gap_px ", merge_gap_px, " must be in [0, 1000]"));
  if (!(min_length_ratio >= 0 && min_length_ratio < 1))
    fail(str("min_length_ratio ", min_length_ratio, " must be in [0, 1)"));
  if (max_lines < 0 || max_lines > 10000) fail(str("max_lines ", max_lines, " must be in 0..10000"));
  if (!(lbd_scale > 0 && lbd_scale <= 1)) fail(str("lbd_scale ", lbd_scale, " must be in (0, 1]"));
}

LineSegment2D LineSegment2D::fromEndpoints(const Eigen::Vector2d& p, const Eigen::Vector2d& q, int octave) {
  LineSegment2D s;
  s.p = p;
  s.q = q;
  const Eigen::Vector2d d = q - p;
  s.length = static_cast<float>(d.norm());
  s.angle = static_cast<float>(std::atan2(d.y(), d.x()));
  s.octave = octave;
  return s;
}

namespace {

// Joins `b` (not longer than `a`) into `a` when they are fragments of one segment.
bool tryMerge(const LineSegment2D& a, const LineSegment2D& b, double cos_max_angle, const LineOptions& o,
              LineSegment2D* out) {
  const double la = a.length, lb = b.length;
  if (la < 1e-9 || lb < 1e-9) return false;
  const Eigen::Vector2d da = (a.q - a.p) / la, db = (b.q - b.p) / lb;
  // Same polarity only: opposite directions are the two sides of a bar, not one edge.
  if (da.dot(db) < cos_max_angle) return false;
  const Eigen::Vector2d na(-da.y(), da.x());
  if (std::abs((b.p - a.p).dot(na)) > o.merge_distance_px || std::abs((b.q - a.p).dot(na)) > o.merge_distance_px)
    return false;
  const double t0 = (b.p - a.p).dot(da), t1 = (b.q - a.p).dot(da);
  const double gap = std::max(std::min(t0, t1) - la, -std::max(t0, t1));
  if (gap > o.merge_gap_px) return false;
  const Eigen::Vector2d dir = (la * da + lb * db).normalized();
  const Eigen::Vector2d centre = (la * (a.p + a.q) + lb * (b.p + b.q)) / (2 * (la + lb));
  double lo = 0, hi = 0;
  bool first = true;
  for (const Eigen::Vector2d* e : {&a.p, &a.q, &b.p, &b.q}) {
    const double t = (*e - centre).dot(dir);
    lo = first ? t : std::min(lo, t);
    hi = first ? t : std::max(hi, t);
    first = false;
  }
  *out = LineSegment2D::fromEndpoints(centre + lo * dir, centre + hi * dir, a.octave);
  return true;
}

void sortLongestFirst(std::vector<LineSegment2D>* segs) {
  std::stable_sort(segs->begin(), segs->end(), [](const LineSegment2D& a, const LineSegment2D& b) { return a.length > b.length; });
}

// The segments by direction, in buckets at least the merge angle wide, so that a segment is
// tested only against those whose direction is in its own or a neighbouring bucket: a
// superset of the pairs within the merge angle (the exact test still decides). Without it
// the merge tested every pair of a frame's raw segments on every pass.
class DirectionBuckets {
 public:
  DirectionBuckets(const std::vector<Eigen::Vector2d>& dirs, double max_angle_rad) {
    constexpr double kMargin = 1e-3;  // radians: the atan2 bucket index never decides a pair alone
    // At least 3 buckets, so that the three searched are distinct (the option range keeps the
    // angle under 45 degrees: 7 buckets or more).
    count_ = std::clamp(static_cast<int>(std::floor(2 * CV_PI / (max_angle_rad + kMargin))), 3, 720);
    members_.resize(static_cast<size_t>(count_));
    bucket_.resize(dirs.size());
    for (size_t i = 0; i < dirs.size(); ++i) add(static_cast<int>(i), dirs[i]);
  }
  void move(int i, const Eigen::Vector2d& dir) {
    remove(i);
    add(i, dir);
  }
  void remove(int i) {
    std::vector<int>& m = members_[static_cast<size_t>(bucket_[static_cast<size_t>(i)])];
    m.erase(std::find(m.begin(), m.end(), i));
  }
  /// The segments after `after` whose direction may be within the angle of `dir`, ascending.
  void near(const Eigen::Vector2d& dir, int after, std::vector<int>* out) const {
    out->clear();
    const int b = bucketOf(dir);
    for (int k = -1; k <= 1; ++k)
      for (int j : members_[static_cast<size_t>((b + k + count_) % count_)])
        if (j > after) out->push_back(j);
    std::sort(out->begin(), out->end());
  }

 private:
  int bucketOf(const Eigen::Vector2d& d) const {
    const double a = std::atan2(d.y(), d.x()) + CV_PI;  // [0, 2 pi]
    return std::min(count_ - 1, static_cast<int>(a / (2 * CV_PI) * count_));
  }
  void add(int i, const Eigen::Vector2d& dir) {
    bucket_[static_cast<size_t>(i)] = bucketOf(dir);
    members_[static_cast<size_t>(bucket_[static_cast<size_t>(i)])].push_back(i);
  }
  int count_ = 1;
  std::vector<std::vector<int>> members_;
  std::vector<int> bucket_;
};

}  // namespace

std::vector<LineSegment2D> mergeSegments(std::vector<LineSegment2D> segs, const LineOptions& o) {
  for (LineSegment2D& s : segs) s = LineSegment2D::fromEndpoints(s.p, s.q, s.octave);  // trust only the endpoints
  sortLongestFirst(&segs);
  const double cos_max = std::cos(o.merge_angle_deg * CV_PI / 180.0);
  const size_t n = segs.size();
  // Unit directions for a cheap first test (refreshed when a segment grows).
  std::vector<Eigen::Vector2d> dir(n);
  for (size_t i = 0; i < n; ++i)
    dir[i] = segs[i].length > 0 ? Eigen::Vector2d((segs[i].q - segs[i].p) / segs[i].length) : Eigen::Vector2d::Zero();
  DirectionBuckets buckets(dir, o.merge_angle_deg * CV_PI / 180.0);
  std::vector<char> dead(n, 0);
  std::vector<int> candidates;
  bool changed = true;
  for (int pass = 0; changed && pass < 100; ++pass) {
    changed = false;
    for (size_t i = 0; i < n; ++i) {
      if (dead[i]) continue;
      buckets.near(dir[i], -1, &candidates);
      for (size_t k = 0; k < candidates.size(); ++k) {
        const size_t j = static_cast<size_t>(candidates[k]);
        if (j == i || dead[j] || dir[i].dot(dir[j]) < cos_max) continue;
        // Join into the longer one; equal lengths: into the earlier one.
        if (segs[j].length > segs[i].length || (segs[j].length == segs[i].length && j < i)) continue;
        LineSegment2D joined;
        if (!tryMerge(segs[i], segs[j], cos_max, o, &joined)) continue;
        segs[i] = joined;
        dir[i] = (joined.q - joined.p) / std::max(1e-9f, joined.length);
        dead[j] = 1;
        changed = true;
        buckets.remove(static_cast<int>(j));
        buckets.move(static_cast<int>(i), dir[i]);
        // The rest of the search follows the new direction, as the scan over all j did.
        buckets.near(dir[i], static_cast<int>(j), &candidates);
        k = static_cast<size_t>(-1);  // the loop's ++k starts the new list
      }
    }
  }
  std::vector<LineSegment2D> out;
  out.reserve(n);
  for (size_t i = 0; i < n; ++i)
    if (!dead[i]) out.push_back(segs[i]);
  sortLongestFirst(&out);
  return out;
}

bool clipSegmentToMask(const cv::Mat& mask, LineSegment2D* s) {
  if (mask.empty()) return true;
  const int n = std::max(2, static_cast<int>(std::ceil(s->length)) + 1);
  int best_start = -1, best_len = 0, run_start = -1;
  for (int k = 0; k <= n; ++k) {
    bool ok = false;
    if (k < n) {
      const Eigen::Vector2d x = s->p + (s->q - s->p) * (double(k) / (n - 1));
      const int u = std::clamp(static_cast<int>(std::lround(x.x())), 0, mask.cols - 1);
      const int v = std::clamp(static_cast<int>(std::lround(x.y())), 0, mask.rows - 1);
      ok = mask.at<uint8_t>(v, u) != 0;
    }
    if (ok && run_start < 0) run_start = k;
    if (!ok && run_start >= 0) {
      if (k - run_start > best_len) {
        best_len = k - run_start;
        best_start = run_start;
      }
      run_start = -1;
    }
  }
  if (best_len < 2) return false;
  if (best_len == n) return true;
  const Eigen::Vector2d d = s->q - s->p;
  *s = LineSegment2D::fromEndpoints(s->p + d * (double(best_start) / (n - 1)),
                                    s->p + d * (double(best_start + best_len - 1) / (n - 1)), s->octave);
  return true;
}

namespace {

// A detector's segment found on the image scaled by `scale` (pixel centres: x_small =
// (x + 0.5) * scale - 0.5, as cv::resize samples), in full-image pixels.
LineSegment2D fromScaled(const cv::Vec4f& r, double scale) {
  auto full = [scale](float x, float y) { return Eigen::Vector2d((x + 0.5) / scale - 0.5, (y + 0.5) / scale - 0.5); };
  return LineSegment2D::fromEndpoints(full(r[0], r[1]), full(r[2], r[3]));
}

std::vector<LineSegment2D> detectLsd(const cv::Mat& grey, const LineOptions& o) {
  std::vector<cv::Vec4f> raw;
  if (o.lsd_refine) {  // OpenCV's, for its refinement; ours is the same detector without it, 4 times faster
    cv::createLineSegmentDetector(cv::LSD_REFINE_STD, o.detect_scale, 0.6, o.lsd_quant)->detect(grey, raw);
  } else {
    LsdParameters lsd;
    lsd.scale = o.detect_scale;
    lsd.quant = o.lsd_quant;
    raw = detectLsdSegments(grey, lsd);
  }
  // Both scale the result back by x / scale, but sample the image with cv::resize: only the
  // half-pixel shift of the pixel centres is left to undo.
  std::vector<LineSegment2D> segs;
  segs.reserve(raw.size());
  const double shift = 0.5 / o.detect_scale - 0.5;
  for (const cv::Vec4f& r : raw)
    segs.push_back(LineSegment2D::fromEndpoints(Eigen::Vector2d(r[0] + shift, r[1] + shift),
                                                Eigen::Vector2d(r[2] + shift, r[3] + shift)));
  return segs;
}

std::vector<LineSegment2D> detectFld(const cv::Mat& grey, const LineOptions& o) {
  cv::Mat small = grey;
  if (o.detect_scale < 1) cv::resize(grey, small, cv::Size(), o.detect_scale, o.detect_scale, cv::INTER_AREA);
  std::vector<cv::Vec4f> raw;
  cv::ximgproc::createFastLineDetector(o.fld_min_length_px, 1.414213562f, o.fld_canny_low, o.fld_canny_high, 3, false)
      ->detect(small, raw);
  std::vector<LineSegment2D> segs;
  segs.reserve(raw.size());
  for (const cv::Vec4f& r : raw) segs.push_back(fromScaled(r, o.detect_scale));
  return segs;
}

}  // namespace

std::vector<LineSegment2D> detectLines(const cv::Mat& image, const cv::Mat& mask, const LineOptions& o, LineStats* stats,
                                       StageTimes* times) {
  o.validate();
  LineStats st;
  std::vector<LineSegment2D> segs;
  const cv::Mat grey = toGrey(image);
  if (!grey.empty()) checkMask(mask, grey.size());
  // LSD needs some room; such small images carry no useful segment anyway.
  if (grey.empty() || grey.cols < 16 || grey.rows < 16 || o.max_lines == 0) {
    if (stats) *stats = st;
    return segs;
  }
  {
    const StageTimer timer(times, Stage::kLsd);
    segs = o.detector == "fld" ? detectFld(grey, o) : detectLsd(grey, o);
  }
  const StageTimer merge_timer(times, Stage::kLineMerge);
  st.detected = static_cast<int>(segs.size());

  segs = mergeSegments(std::move(segs), o);
  st.merged = static_cast<int>(segs.size());

  const double min_len = o.min_length_ratio * std::hypot(grey.cols, grey.rows);
  std::vector<LineSegment2D> out;
  out.reserve(segs.size());
  for (LineSegment2D& s : segs) {
    if (!clipSegmentToMask(mask, &s)) continue;
    ++st.unmasked;
    if (s.length < min_len) continue;
    out.push_back(s);
  }
  st.long_enough = static_cast<int>(out.size());
  sortLongestFirst(&out);  // clipping may have changed the order
  if (static_cast<int>(out.size()) > o.max_lines) out.resize(static_cast<size_t>(o.max_lines));
  st.kept = static_cast<int>(out.size());
  if (stats) *stats = st;
  return out;
}

cv::Mat describeLines(const cv::Mat& image, const std::vector<LineSegment2D>& lines, const LineOptions& o) {
  o.validate();
  const cv::Mat grey = toGrey(image);
  if (lines.empty() || grey.empty()) return cv::Mat(0, 32, CV_8U);
  const double s = o.lbd_scale;
  cv::Mat img = grey;
  if (s < 1) cv::resize(grey, img, cv::Size(), s, s, cv::INTER_AREA);
  std::vector<LbdSegment> segments;
  segments.reserve(lines.size());
  for (const LineSegment2D& line : lines) {
    // INTER_AREA maps pixel centres x -> (x + 0.5) * s - 0.5.
    const Eigen::Vector2d p = (line.p.array() + 0.5) * s - 0.5, q = (line.q.array() + 0.5) * s - 0.5;
    LbdSegment seg;
    seg.start_x = static_cast<float>(p.x()), seg.start_y = static_cast<float>(p.y());
    seg.end_x = static_cast<float>(q.x()), seg.end_y = static_cast<float>(q.y());
    seg.angle = static_cast<float>(std::atan2(q.y() - p.y(), q.x() - p.x()));
    // The support region runs one sample per pixel along the whole length.
    seg.samples = std::max(1, static_cast<int>(std::lround((q - p).norm())));
    segments.push_back(seg);
  }
  return describeLbd(img, segments);
}

}  // namespace plslam
