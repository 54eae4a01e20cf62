#include "features/matching.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"

namespace plslam {

void bindBruteForceOptions(OptionTable* t, const std::string& p, BruteForceOptions* o) {
  t->bind(p + "max_distance", &o->max_distance, "ORB Hamming distance accepted (of 256 bits)", within(0, 256));
  t->bind(p + "ratio", &o->ratio, "best < ratio * second-best distance (1: no ratio test)", Range{0, 1, true});
  t->bind(p + "mutual", &o->mutual, "keep a pair only if each is the other's best");
}

namespace {

// Bit-parallel popcount: the build uses no -mpopcnt, where __builtin_popcountll is a call.
inline int popcount64(uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ULL);
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
  return static_cast<int>((x * 0x0101010101010101ULL) >> 56);
}

void checkDescriptors(const cv::Mat& d, const char* what) {
  if (d.empty()) return;
  if (d.type() != CV_8UC1 || d.cols != 32 || !d.isContinuous())
    throw DataError(str("features: ", what, " descriptors are ", d.rows, "x", d.cols, " ", cv::typeToString(d.type()),
                        ", expected continuous Nx32 CV_8UC1"));
}

void checkRows(const cv::Mat& d, size_t n, const char* what) {
  if (static_cast<size_t>(d.rows) != n)
    throw DataError(str("features: ", n, " ", what, " but ", d.rows, " descriptor rows"));
}

// The closest candidate (ties: the lower index) and the second-closest distance. The result
// does not depend on the order of the offers, so a grid query need not sort its candidates.
struct Best {
  int distance = INT_MAX, second = INT_MAX, index = -1;
  void offer(int d, int i) {
    if (d < distance || (d == distance && i < index)) {
      second = distance;
      distance = d;
      index = i;
    } else if (d < second) {
      second = d;
    }
  }
  bool accepted(int max_distance, float ratio) const {
    if (index < 0 || distance > max_distance) return false;
    return !(ratio < 1.0f && second != INT_MAX && distance >= ratio * second);
  }
};

// Each train index keeps only its closest query (ties: the lower query index); sorted by query.
std::vector<DescriptorMatch> uniqueTrain(const std::vector<DescriptorMatch>& proposals, size_t n_train) {
  std::vector<int> owner(n_train, -1);
  for (size_t i = 0; i < proposals.size(); ++i) {
    int& o = owner[static_cast<size_t>(proposals[i].train)];
    if (o < 0 || proposals[i].distance < proposals[static_cast<size_t>(o)].distance) o = static_cast<int>(i);
  }
  std::vector<DescriptorMatch> out;
  for (size_t i = 0; i < proposals.size(); ++i)
    if (owner[static_cast<size_t>(proposals[i].train)] == static_cast<int>(i)) out.push_back(proposals[i]);
  return out;  // proposals come in query order
}

}  // namespace

int hammingDistance(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int i = 0; i < 4; ++i) {
    uint64_t x, y;
    std::memcpy(&x, a + 8 * i, 8);
    std::memcpy(&y, b + 8 * i, 8);
    d += popcount64(x ^ y);
  }
  return d;
}

std::vector<DescriptorMatch> matchBruteForce(const cv::Mat& query, const cv::Mat& train, const BruteForceOptions& o) {
  checkDescriptors(query, "query");
  checkDescriptors(train, "train");
  if (query.empty() || train.empty()) return {};
  const int nq = query.rows, nt = train.rows;
  std::vector<int> train_best(static_cast<size_t>(nt), INT_MAX), train_best_query(static_cast<size_t>(nt), -1);
  std::vector<Best> best(static_cast<size_t>(nq));
  for (int q = 0; q < nq; ++q) {
    const uint8_t* dq = query.ptr<uint8_t>(q);
    Best& b = best[static_cast<size_t>(q)];
    for (int t = 0; t < nt; ++t) {
      const int d = hammingDistance(dq, train.ptr<uint8_t>(t));
      b.offer(d, t);
      if (d < train_best[static_cast<size_t>(t)]) {
        train_best[static_cast<size_t>(t)] = d;
        train_best_query[static_cast<size_t>(t)] = q;
      }
    }
  }
  std::vector<DescriptorMatch> proposals;
  for (int q = 0; q < nq; ++q) {
    const Best& b = best[static_cast<size_t>(q)];
    if (!b.accepted(o.max_distance, o.ratio)) continue;
    if (o.mutual && train_best_query[static_cast<size_t>(b.index)] != q) continue;
    proposals.push_back({q, b.index, b.distance});
  }
  return uniqueTrain(proposals, static_cast<size_t>(nt));
}

std::vector<DescriptorMatch> filterByOrientation(const std::vector<DescriptorMatch>& matches,
                                                 const std::vector<float>& qa, const std::vector<float>& ta,
                                                 const OrientationOptions& o) {
  if (matches.empty() || o.bins <= 0) return matches;
  std::vector<int> bin_of(matches.size());
  std::vector<int> count(static_cast<size_t>(o.bins), 0);
  for (size_t i = 0; i < matches.size(); ++i) {
    const size_t q = static_cast<size_t>(matches[i].query), t = static_cast<size_t>(matches[i].train);
    if (q >= qa.size() || t >= ta.size()) throw DataError("features: filterByOrientation: match index out of range");
    double diff = std::fmod(double(ta[t]) - double(qa[q]), 360.0);
    if (diff < 0) diff += 360.0;
    const int b = std::min(o.bins - 1, static_cast<int>(diff * o.bins / 360.0));
    bin_of[i] = b;
    ++count[static_cast<size_t>(b)];
  }
  std::vector<int> order(static_cast<size_t>(o.bins));
  for (int b = 0; b < o.bins; ++b) order[static_cast<size_t>(b)] = b;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return count[size_t(a)] > count[size_t(b)]; });
  std::vector<char> keep(static_cast<size_t>(o.bins), 0);
  const int top = count[static_cast<size_t>(order[0])];
  for (int k = 0; k < std::min(o.keep_bins, o.bins); ++k) {
    const int c = count[static_cast<size_t>(order[static_cast<size_t>(k)])];
    if (c > 0 && (k == 0 || c >= o.min_bin_ratio * top)) keep[static_cast<size_t>(order[static_cast<size_t>(k)])] = 1;
  }
  std::vector<DescriptorMatch> out;
  for (size_t i = 0; i < matches.size(); ++i)
    if (keep[static_cast<size_t>(bin_of[i])]) out.push_back(matches[i]);
  return out;
}

PointGrid::PointGrid(std::vector<Eigen::Vector2d> points, int width, int height, int cell_size)
    : points_(std::move(points)), cell_(std::max(1, cell_size)) {
  cols_ = std::max(1, (width + cell_ - 1) / cell_);
  rows_ = std::max(1, (height + cell_ - 1) / cell_);
  auto cellIndex = [&](const Eigen::Vector2d& p) {
    const double fx = std::isfinite(p.x()) ? std::floor(p.x() / cell_) : 0.0;
    const double fy = std::isfinite(p.y()) ? std::floor(p.y() / cell_) : 0.0;
    const int cx = static_cast<int>(std::clamp(fx, 0.0, double(cols_ - 1)));
    const int cy = static_cast<int>(std::clamp(fy, 0.0, double(rows_ - 1)));
    return cy * cols_ + cx;
  };
  const size_t n_cells = static_cast<size_t>(cols_) * rows_;
  start_.assign(n_cells + 1, 0);
  std::vector<int> cell_of(points_.size());
  for (size_t i = 0; i < points_.size(); ++i) {
    cell_of[i] = cellIndex(points_[i]);
    ++start_[static_cast<size_t>(cell_of[i]) + 1];
  }
  for (size_t c = 0; c < n_cells; ++c) start_[c + 1] += start_[c];
  order_.resize(points_.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) order_[static_cast<size_t>(fill[static_cast<size_t>(cell_of[i])]++)] = static_cast<int>(i);
  cell_points_.reserve(points_.size());
  for (int i : order_) cell_points_.push_back(points_[static_cast<size_t>(i)]);
}

void PointGrid::query(const Eigen::Vector2d& c, double radius, std::vector<int>* out) const {
  out->clear();
  if (points_.empty() || !(radius >= 0) || !c.allFinite()) return;
  auto clampCell = [](double v, int n) { return static_cast<int>(std::clamp(std::floor(v), 0.0, double(n - 1))); };
  const int x0 = clampCell((c.x() - radius) / cell_, cols_), x1 = clampCell((c.x() + radius) / cell_, cols_);
  const int y0 = clampCell((c.y() - radius) / cell_, rows_), y1 = clampCell((c.y() + radius) / cell_, rows_);
  const double r2 = radius * radius;
  for (int y = y0; y <= y1; ++y) {
    // Cells x0..x1 of a row are consecutive in order_.
    const size_t row = static_cast<size_t>(y) * cols_;
    const int end = start_[row + x1 + 1];
    for (int k = start_[row + x0]; k < end; ++k) {
      const size_t slot = static_cast<size_t>(k);
      if ((cell_points_[slot] - c).squaredNorm() <= r2) out->push_back(order_[slot]);
    }
  }
}

std::vector<DescriptorMatch> matchPointsByProjection(const std::vector<PointPrediction>& predictions,
                                                     const cv::Mat& prediction_descriptors, const PointGrid& grid,
                                                     const std::vector<int>& octaves, const cv::Mat& descriptors,
                                                     const PointProjectionOptions& o, const std::vector<char>& excluded) {
  checkDescriptors(prediction_descriptors, "prediction");
  checkDescriptors(descriptors, "frame");
  if (predictions.empty() || grid.size() == 0) return {};
  checkRows(prediction_descriptors, predictions.size(), "predictions");
  checkRows(descriptors, grid.size(), "keypoints");
  if (!octaves.empty() && octaves.size() != grid.size())
    throw DataError(str("features: ", grid.size(), " keypoints but ", octaves.size(), " octaves"));
  std::vector<DescriptorMatch> proposals;
  std::vector<int> cand;
  for (size_t i = 0; i < predictions.size(); ++i) {
    const PointPrediction& pr = predictions[i];
    const double radius = o.radius_px * (pr.octave > 0 ? std::pow(o.octave_radius_factor, pr.octave) : 1.0);
    grid.query(pr.uv, radius, &cand);
    const uint8_t* dp = prediction_descriptors.ptr<uint8_t>(static_cast<int>(i));
    Best b;
    for (int k : cand) {
      if (static_cast<size_t>(k) < excluded.size() && excluded[static_cast<size_t>(k)]) continue;
      if (pr.octave >= 0 && o.octave_window >= 0 && !octaves.empty() &&
          std::abs(octaves[static_cast<size_t>(k)] - pr.octave) > o.octave_window)
        continue;
      b.offer(hammingDistance(dp, descriptors.ptr<uint8_t>(k)), k);
    }
    if (b.accepted(o.max_distance, o.ratio)) proposals.push_back({static_cast<int>(i), b.index, b.distance});
  }
  return uniqueTrain(proposals, grid.size());
}

std::vector<DescriptorMatch> matchLinesByProjection(const std::vector<LineSegment2D>& predictions,
                                                    const cv::Mat& prediction_descriptors,
                                                    const std::vector<LineSegment2D>& lines, const cv::Mat& descriptors,
                                                    const LineProjectionOptions& o, const std::vector<char>& excluded) {
  checkDescriptors(prediction_descriptors, "prediction");
  checkDescriptors(descriptors, "frame");
  if (predictions.empty() || lines.empty()) return {};
  checkRows(prediction_descriptors, predictions.size(), "predicted lines");
  checkRows(descriptors, lines.size(), "lines");
  const double cos_max = std::cos(o.angle_deg * CV_PI / 180.0);
  // Directions and midpoints of the frame's segments, once.
  std::vector<Eigen::Vector2d> dir(lines.size()), mid(lines.size());
  std::vector<double> len(lines.size());
  for (size_t j = 0; j < lines.size(); ++j) {
    const Eigen::Vector2d d = lines[j].q - lines[j].p;
    len[j] = d.norm();
    dir[j] = len[j] > 1e-9 ? Eigen::Vector2d(d / len[j]) : Eigen::Vector2d::Zero();
    mid[j] = 0.5 * (lines[j].p + lines[j].q);
  }
  std::vector<DescriptorMatch> proposals;
  for (size_t i = 0; i < predictions.size(); ++i) {
    const LineSegment2D& pr = predictions[i];
    const Eigen::Vector2d d = pr.q - pr.p;
    const double lp = d.norm();
    if (!(lp >= o.min_length_px) || !d.allFinite()) continue;
    const Eigen::Vector2d u = d / lp, n(-u.y(), u.x());
    const uint8_t* dp = prediction_descriptors.ptr<uint8_t>(static_cast<int>(i));
    Best b;
    for (size_t j = 0; j < lines.size(); ++j) {
      if (j < excluded.size() && excluded[j]) continue;
      if (len[j] <= 1e-9 || std::abs(u.dot(dir[j])) < cos_max) continue;
      if (std::abs((mid[j] - pr.p).dot(n)) > o.distance_px) continue;
      double t0 = (lines[j].p - pr.p).dot(u), t1 = (lines[j].q - pr.p).dot(u);
      if (t0 > t1) std::swap(t0, t1);
      const double overlap = std::min(t1, lp) - std::max(t0, 0.0);
      if (overlap <= 0 || overlap < o.min_overlap * std::min(lp, len[j])) continue;
      b.offer(hammingDistance(dp, descriptors.ptr<uint8_t>(static_cast<int>(j))), static_cast<int>(j));
    }
    if (b.accepted(o.max_distance, o.ratio)) proposals.push_back({static_cast<int>(i), b.index, b.distance});
  }
  return uniqueTrain(proposals, lines.size());
}

}  // namespace plslam
