#include "frontend/projection_search.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

namespace plslam {

int hamming32(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int i = 0; i < 4; ++i) {
    uint64_t x, y;
    std::memcpy(&x, a + 8 * i, 8);
    std::memcpy(&y, b + 8 * i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

namespace {

// Keypoints bucketed by ideal position, for window queries.
class KeypointGrid {
 public:
  explicit KeypointGrid(const std::vector<Keypoint>& kps) {
    for (size_t i = 0; i < kps.size(); ++i) {
      min_x_ = std::min(min_x_, kps[i].uv.x());
      min_y_ = std::min(min_y_, kps[i].uv.y());
      max_x_ = std::max(max_x_, kps[i].uv.x());
      max_y_ = std::max(max_y_, kps[i].uv.y());
    }
    if (kps.empty()) return;
    cols_ = static_cast<int>((max_x_ - min_x_) / kCell) + 1;
    rows_ = static_cast<int>((max_y_ - min_y_) / kCell) + 1;
    cells_.resize(static_cast<size_t>(cols_) * rows_);
    for (size_t i = 0; i < kps.size(); ++i) cells_[cell(kps[i].uv.x(), kps[i].uv.y())].push_back(static_cast<int>(i));
  }
  template <typename F>
  void forEachNear(const Eigen::Vector2d& uv, double r, F&& f) const {
    if (cells_.empty()) return;
    const int x0 = std::max(0, static_cast<int>(std::floor((uv.x() - r - min_x_) / kCell)));
    const int x1 = std::min(cols_ - 1, static_cast<int>(std::floor((uv.x() + r - min_x_) / kCell)));
    const int y0 = std::max(0, static_cast<int>(std::floor((uv.y() - r - min_y_) / kCell)));
    const int y1 = std::min(rows_ - 1, static_cast<int>(std::floor((uv.y() + r - min_y_) / kCell)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (int i : cells_[static_cast<size_t>(y) * cols_ + x]) f(i);
  }

 private:
  static constexpr double kCell = 16.0;
  size_t cell(double u, double v) const {
    return static_cast<size_t>(static_cast<int>((v - min_y_) / kCell)) * cols_ + static_cast<int>((u - min_x_) / kCell);
  }
  double min_x_ = 1e18, min_y_ = 1e18, max_x_ = -1e18, max_y_ = -1e18;
  int cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> cells_;
};

}  // namespace

std::vector<int> searchPointsByProjection(const std::vector<ProjectedPoint>& projected, const FrameFeatures& f,
                                          const ProjectionSearchOptions& o, const std::vector<Id>& taken) {
  std::vector<int> out(projected.size(), -1);
  if (f.points.empty() || f.point_descriptors.empty()) return out;
  const KeypointGrid grid(f.points);
  std::vector<int> best_dist(f.points.size(), INT_MAX);
  std::vector<int> owner(f.points.size(), -1);
  const double r2 = o.radius_px * o.radius_px;
  for (size_t i = 0; i < projected.size(); ++i) {
    const ProjectedPoint& p = projected[i];
    int best = INT_MAX, second = INT_MAX, best_kp = -1;
    grid.forEachNear(p.uv, o.radius_px, [&](int k) {
      if (k < static_cast<int>(taken.size()) && taken[k] != kNoId && taken[k] != p.id) return;
      if ((f.points[k].uv - p.uv).squaredNorm() > r2) return;
      const int d = hamming32(p.descriptor.ptr<uint8_t>(0), f.point_descriptors.ptr<uint8_t>(k));
      if (d < best) {
        second = best;
        best = d;
        best_kp = k;
      } else if (d < second) {
        second = d;
      }
    });
    if (best_kp < 0 || best > o.max_distance) continue;
    if (second != INT_MAX && best > o.ratio * second) continue;
    if (best >= best_dist[best_kp]) continue;
    if (owner[best_kp] >= 0) out[owner[best_kp]] = -1;
    owner[best_kp] = static_cast<int>(i);
    best_dist[best_kp] = best;
    out[i] = best_kp;
  }
  return out;
}

std::vector<int> searchLinesByProjection(const std::vector<ProjectedLine>& projected, const FrameFeatures& f,
                                         const LineSearchOptions& o, const std::vector<Id>& taken) {
  std::vector<int> out(projected.size(), -1);
  if (f.lines.empty() || f.line_descriptors.empty()) return out;
  std::vector<int> best_dist(f.lines.size(), INT_MAX), owner(f.lines.size(), -1);
  const double cos_max = std::cos(o.angle_deg * M_PI / 180.0);
  for (size_t i = 0; i < projected.size(); ++i) {
    const ProjectedLine& pl = projected[i];
    Eigen::Vector2d dir = pl.q - pl.p;
    const double len = dir.norm();
    if (len < 5) continue;
    dir /= len;
    const Eigen::Vector2d normal(-dir.y(), dir.x());
    int best = INT_MAX, best_line = -1;
    for (size_t j = 0; j < f.lines.size(); ++j) {
      if (j < taken.size() && taken[j] != kNoId && taken[j] != pl.id) continue;
      const Segment2D& s = f.lines[j];
      Eigen::Vector2d d2 = s.q - s.p;
      const double l2 = d2.norm();
      if (l2 < 1e-6) continue;
      if (std::abs(d2.dot(dir)) / l2 < cos_max) continue;
      if (std::abs((s.p - pl.p).dot(normal)) > o.distance_px || std::abs((s.q - pl.p).dot(normal)) > o.distance_px)
        continue;
      // The segments must overlap along the line.
      double a = (s.p - pl.p).dot(dir), b = (s.q - pl.p).dot(dir);
      if (a > b) std::swap(a, b);
      if (std::min(b, len) - std::max(a, 0.0) <= 0) continue;
      const int d = hamming32(pl.descriptor.ptr<uint8_t>(0), f.line_descriptors.ptr<uint8_t>(static_cast<int>(j)));
      if (d < best) {
        best = d;
        best_line = static_cast<int>(j);
      }
    }
    if (best_line < 0 || best > o.max_distance || best >= best_dist[best_line]) continue;
    if (owner[best_line] >= 0) out[owner[best_line]] = -1;
    owner[best_line] = static_cast<int>(i);
    best_dist[best_line] = best;
    out[i] = best_line;
  }
  return out;
}

std::vector<int> matchDescriptors(const cv::Mat& a, const cv::Mat& b, int max_distance, float ratio) {
  std::vector<int> out(a.rows, -1);
  std::vector<int> best_dist(b.rows, INT_MAX), owner(b.rows, -1);
  for (int i = 0; i < a.rows; ++i) {
    int best = INT_MAX, second = INT_MAX, best_j = -1;
    for (int j = 0; j < b.rows; ++j) {
      const int d = hamming32(a.ptr<uint8_t>(i), b.ptr<uint8_t>(j));
      if (d < best) {
        second = best;
        best = d;
        best_j = j;
      } else if (d < second) {
        second = d;
      }
    }
    if (best_j < 0 || best > max_distance || (second != INT_MAX && best > ratio * second)) continue;
    if (best >= best_dist[best_j]) continue;
    if (owner[best_j] >= 0) out[owner[best_j]] = -1;
    owner[best_j] = i;
    best_dist[best_j] = best;
    out[i] = best_j;
  }
  return out;
}

}  // namespace plslam
