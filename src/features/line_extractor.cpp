#include "features/line_extractor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/line_descriptor.hpp>

namespace plslam {

namespace {

// Tries to join a and b; on success writes the joined segment (the extreme projections
// of the four endpoints on a's direction, placed on the length-weighted mean line).
bool tryMerge(const LineSegment2D& a, const LineSegment2D& b, const LineOptions& o, LineSegment2D* out) {
  const double la = a.length(), lb = b.length();
  if (la < 1e-6 || lb < 1e-6) return false;
  Eigen::Vector2d da = (a.q - a.p) / la, db = (b.q - b.p) / lb;
  if (da.dot(db) < 0) db = -db;
  if (da.dot(db) < std::cos(o.merge_angle_deg * M_PI / 180.0)) return false;
  const Eigen::Vector2d na(-da.y(), da.x()), nb(-db.y(), db.x());
  if (std::abs((b.p - a.p).dot(na)) > o.merge_distance_px || std::abs((b.q - a.p).dot(na)) > o.merge_distance_px ||
      std::abs((a.p - b.p).dot(nb)) > o.merge_distance_px || std::abs((a.q - b.p).dot(nb)) > o.merge_distance_px)
    return false;
  const double b0 = (b.p - a.p).dot(da), b1 = (b.q - a.p).dot(da);
  const double gap = std::max(std::min(b0, b1) - la, -std::max(b0, b1));
  if (gap > o.merge_gap_px) return false;
  Eigen::Vector2d dir = (la * da + lb * db).normalized();
  const Eigen::Vector2d centre = (la * 0.5 * (a.p + a.q) + lb * 0.5 * (b.p + b.q)) / (la + lb);
  double lo = 1e18, hi = -1e18;
  for (const Eigen::Vector2d& e : {a.p, a.q, b.p, b.q}) {
    const double t = (e - centre).dot(dir);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  out->p = centre + lo * dir;
  out->q = centre + hi * dir;
  return true;
}

}  // namespace

std::vector<LineSegment2D> mergeSegments(std::vector<LineSegment2D> segs, const LineOptions& o) {
  // Longest first so that short fragments join the long edges they belong to.
  std::stable_sort(segs.begin(), segs.end(), [](const auto& a, const auto& b) { return a.length() > b.length(); });
  bool changed = true;
  while (changed) {
    changed = false;
    for (size_t i = 0; i < segs.size(); ++i) {
      for (size_t j = i + 1; j < segs.size(); ++j) {
        LineSegment2D merged;
        if (tryMerge(segs[i], segs[j], o, &merged)) {
          segs[i] = merged;
          segs.erase(segs.begin() + static_cast<long>(j));
          changed = true;
          --j;
        }
      }
    }
  }
  return segs;
}

std::vector<LineSegment2D> detectLines(const cv::Mat& grey, const cv::Mat& mask, const LineOptions& o, LineStats* stats) {
  LineStats st;
  std::vector<LineSegment2D> out;
  if (grey.empty() || grey.cols < 16 || grey.rows < 16) {
    if (stats) *stats = st;
    return out;
  }
  CV_Assert(grey.type() == CV_8UC1);
  cv::Mat small;
  const double s = o.detect_scale > 0 && o.detect_scale < 1 ? o.detect_scale : 1.0;
  if (s < 1) cv::resize(grey, small, cv::Size(), s, s, cv::INTER_AREA);
  else small = grey;
  std::vector<cv::Vec4f> raw;
  cv::createLineSegmentDetector(cv::LSD_REFINE_NONE)->detect(small, raw);
  st.detected = static_cast<int>(raw.size());
  std::vector<LineSegment2D> segs;
  segs.reserve(raw.size());
  for (const cv::Vec4f& r : raw) segs.push_back({Eigen::Vector2d(r[0], r[1]) / s, Eigen::Vector2d(r[2], r[3]) / s});
  segs = mergeSegments(std::move(segs), o);
  st.merged = static_cast<int>(segs.size());
  const double min_len = o.min_length_ratio * std::hypot(grey.cols, grey.rows);
  const bool use_mask = !mask.empty() && mask.size() == grey.size() && mask.type() == CV_8UC1;
  for (const LineSegment2D& seg : segs) {
    if (seg.length() < min_len) continue;
    if (use_mask) {
      int masked = 0, n = 0;
      for (double t = 0; t <= 1.0; t += 0.1, ++n) {
        const Eigen::Vector2d x = seg.p + t * (seg.q - seg.p);
        const int u = std::clamp(static_cast<int>(std::lround(x.x())), 0, mask.cols - 1);
        const int v = std::clamp(static_cast<int>(std::lround(x.y())), 0, mask.rows - 1);
        masked += mask.at<uint8_t>(v, u) == 0;
      }
      if (masked > o.masked_fraction * n) continue;
    }
    out.push_back(seg);
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.length() > b.length(); });
  if (static_cast<int>(out.size()) > o.max_lines) out.resize(o.max_lines);
  st.kept = static_cast<int>(out.size());
  if (stats) *stats = st;
  return out;
}

cv::Mat describeLines(const cv::Mat& grey, const std::vector<LineSegment2D>& lines, const LineOptions& o) {
  if (lines.empty() || grey.empty()) return cv::Mat(0, 32, CV_8U);
  using cv::line_descriptor::KeyLine;
  const double s = o.lbd_scale > 0 && o.lbd_scale < 1 ? o.lbd_scale : 1.0;
  cv::Mat img;
  if (s < 1) cv::resize(grey, img, cv::Size(), s, s, cv::INTER_AREA);
  else img = grey;
  std::vector<KeyLine> kls;
  kls.reserve(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    const Eigen::Vector2d p = lines[i].p * s, q = lines[i].q * s;
    KeyLine k;
    k.startPointX = k.sPointInOctaveX = static_cast<float>(p.x());
    k.startPointY = k.sPointInOctaveY = static_cast<float>(p.y());
    k.endPointX = k.ePointInOctaveX = static_cast<float>(q.x());
    k.endPointY = k.ePointInOctaveY = static_cast<float>(q.y());
    k.lineLength = static_cast<float>((q - p).norm());
    k.angle = static_cast<float>(std::atan2(q.y() - p.y(), q.x() - p.x()));
    k.octave = 0;
    k.class_id = static_cast<int>(i);  // LBD keeps the order of class ids
    k.pt = cv::Point2f(static_cast<float>(0.5 * (p.x() + q.x())), static_cast<float>(0.5 * (p.y() + q.y())));
    k.size = k.lineLength;
    k.response = k.lineLength / std::max(img.cols, img.rows);
    k.numOfPixels = static_cast<int>(k.lineLength);
    kls.push_back(k);
  }
  cv::line_descriptor::BinaryDescriptor::Params params;
  params.numOfOctave_ = 1;  // one level: the segments are given, not detected
  cv::Mat desc;
  cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor(params)->compute(img, kls, desc);
  CV_Assert(desc.rows == static_cast<int>(lines.size()) && desc.cols == 32 && desc.type() == CV_8U);
  return desc;
}

}  // namespace plslam
