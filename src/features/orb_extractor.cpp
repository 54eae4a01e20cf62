#include "features/orb_extractor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <queue>
#include <tuple>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

void OrbOptions::validate() const {
  auto fail = [](const std::string& m) { throw ConfigError("features.orb: " + m); };
  if (num_features < 0 || num_features > 100000) fail(str("num_features ", num_features, " must be in 0..100000"));
  if (!(scale_factor > 1.0f && scale_factor <= 4.0f)) fail(str("scale_factor ", scale_factor, " must be in (1, 4]"));
  if (num_levels < 1 || num_levels > 32) fail(str("num_levels ", num_levels, " must be in 1..32"));
  if (fast_threshold < 1 || fast_threshold > 254) fail(str("fast_threshold ", fast_threshold, " must be in 1..254"));
  if (min_fast_threshold < 1 || min_fast_threshold > fast_threshold)
    fail(str("min_fast_threshold ", min_fast_threshold, " must be in 1..fast_threshold (", fast_threshold, ")"));
  if (cell_size < 8 || cell_size > 1000) fail(str("cell_size ", cell_size, " must be in 8..1000"));
}

std::vector<float> orbLevelScales(const OrbOptions& o) {
  std::vector<float> s(static_cast<size_t>(std::max(1, o.num_levels)));
  // Computed as cv::ORB does, so that its descriptor pyramid matches ours level by level.
  for (size_t l = 0; l < s.size(); ++l) s[l] = static_cast<float>(std::pow(static_cast<double>(o.scale_factor), double(l)));
  return s;
}

cv::Mat toGrey(const cv::Mat& image) {
  if (image.empty() || image.type() == CV_8UC1) return image;
  cv::Mat grey;
  if (image.type() == CV_8UC3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else if (image.type() == CV_8UC4) cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  else throw DataError("features: image type " + cv::typeToString(image.type()) + " is not CV_8UC1, CV_8UC3 or CV_8UC4");
  return grey;
}

void checkMask(const cv::Mat& mask, const cv::Size& size) {
  if (mask.empty()) return;
  if (mask.type() != CV_8UC1 || mask.size() != size)
    throw DataError(str("features: mask ", mask.cols, "x", mask.rows, " ", cv::typeToString(mask.type()),
                        " does not match the ", size.width, "x", size.height, " image (CV_8UC1 expected)"));
}

namespace {

constexpr int kHalfPatch = 15;

using Candidate = OrbExtraction::Candidate;

// Half-width of the circular patch at each row offset: the pixels with u^2 + v^2 <= r^2 + r.
// Defined by a condition symmetric in u and v, so the patch is the same after a 90 degree
// rotation and so is the orientation (up to the rotation).
const std::array<int, kHalfPatch + 1>& circleHalfWidths() {
  static const std::array<int, kHalfPatch + 1> table = [] {
    std::array<int, kHalfPatch + 1> t{};
    const int r2 = kHalfPatch * kHalfPatch + kHalfPatch;
    for (int v = 0; v <= kHalfPatch; ++v) {
      int u = 0;
      while ((u + 1) * (u + 1) + v * v <= r2 && u < kHalfPatch) ++u;
      t[v] = u;
    }
    return t;
  }();
  return table;
}

// Orientation by the intensity centroid of the circular patch (Rosin; ORB), degrees [0, 360).
float intensityCentroidAngle(const cv::Mat& img, int x, int y) {
  const auto& hw = circleHalfWidths();
  long m10 = 0, m01 = 0;
  const uint8_t* centre = img.ptr<uint8_t>(y) + x;
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * centre[u];
  const size_t step = img.step1();
  for (int v = 1; v <= kHalfPatch; ++v) {
    const uint8_t* below = centre + v * step;
    const uint8_t* above = centre - v * step;
    long row_sum = 0;
    for (int u = -hw[v]; u <= hw[v]; ++u) {
      m10 += u * (below[u] + above[u]);
      row_sum += below[u] - above[u];
    }
    m01 += v * row_sum;
  }
  float a = static_cast<float>(std::atan2(double(m01), double(m10)) * 180.0 / CV_PI);
  if (a < 0) a += 360.0f;
  if (a >= 360.0f) a -= 360.0f;
  return a;
}

// Keeps at most `target` candidates spread over the region: splits the most populated
// quadtree node until there are `target` nodes, then keeps the strongest of each node.
// The nodes are ranges of one index array, partitioned in place on each split (no vector per
// node); ties between equally strong candidates go to the lower index, whatever the order in
// the range.
std::vector<int> distributeQuadtree(const std::vector<Candidate>& c, int target, float x0, float y0, float x1, float y1) {
  std::vector<int> out;
  if (target <= 0 || c.empty()) return out;
  std::vector<int> idx(c.size());
  for (size_t i = 0; i < c.size(); ++i) idx[i] = static_cast<int>(i);
  if (static_cast<int>(c.size()) <= target) return idx;
  struct Node {
    float x0, y0, x1, y1;
    int begin, end;  // its candidates: idx[begin, end)
    bool alive = true;
    int count() const { return end - begin; }
  };
  std::vector<Node> nodes;
  nodes.push_back({x0, y0, x1, y1, 0, static_cast<int>(c.size()), true});
  // Most points first; among equals the oldest node, so the order is deterministic.
  using Entry = std::pair<int, int>;  // (count, -node index)
  std::priority_queue<Entry> heap;
  heap.push({static_cast<int>(c.size()), 0});
  int leaves = 1;
  while (leaves < target && !heap.empty()) {
    const int n = -heap.top().second;
    heap.pop();
    nodes[static_cast<size_t>(n)].alive = false;
    const Node parent = nodes[static_cast<size_t>(n)];
    const float mx = 0.5f * (parent.x0 + parent.x1), my = 0.5f * (parent.y0 + parent.y1);
    auto first = idx.begin() + parent.begin, last = idx.begin() + parent.end;
    const auto bottom = std::partition(first, last, [&](int i) { return c[static_cast<size_t>(i)].y < my; });
    const auto isLeft = [&](int i) { return c[static_cast<size_t>(i)].x < mx; };
    const auto top_right = std::partition(first, bottom, isLeft);
    const auto bottom_right = std::partition(bottom, last, isLeft);
    auto at = [&](std::vector<int>::iterator it) { return static_cast<int>(it - idx.begin()); };
    const std::array<Node, 4> child = {Node{parent.x0, parent.y0, mx, my, parent.begin, at(top_right)},
                                       Node{mx, parent.y0, parent.x1, my, at(top_right), at(bottom)},
                                       Node{parent.x0, my, mx, parent.y1, at(bottom), at(bottom_right)},
                                       Node{mx, my, parent.x1, parent.y1, at(bottom_right), parent.end}};
    --leaves;
    for (const Node& ch : child) {
      if (ch.count() == 0) continue;
      ++leaves;
      const bool splittable = ch.count() > 1 && (ch.x1 - ch.x0) > 1.0f && (ch.y1 - ch.y0) > 1.0f;
      nodes.push_back(ch);
      if (splittable) heap.push({ch.count(), -static_cast<int>(nodes.size() - 1)});
    }
  }
  for (const Node& nd : nodes) {
    if (!nd.alive || nd.count() == 0) continue;
    int best = idx[static_cast<size_t>(nd.begin)];
    for (int k = nd.begin; k < nd.end; ++k) {
      const int i = idx[static_cast<size_t>(k)];
      if (c[i].response > c[best].response || (c[i].response == c[best].response && i < best)) best = i;
    }
    out.push_back(best);
  }
  if (static_cast<int>(out.size()) > target) {
    std::stable_sort(out.begin(), out.end(), [&](int a, int b) {
      return std::tie(c[b].response, a) < std::tie(c[a].response, b);  // strongest first, then index
    });
    out.resize(target);
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool allowed(const cv::Mat& mask, float x0, float y0) {
  if (mask.empty()) return true;
  const int x = std::clamp(static_cast<int>(std::lround(x0)), 0, mask.cols - 1);
  const int y = std::clamp(static_cast<int>(std::lround(y0)), 0, mask.rows - 1);
  return mask.at<uint8_t>(y, x) != 0;
}

// FAST corners of one level inside [kOrbEdge, size - kOrbEdge), mask-filtered, with the
// lower threshold in the cells where the normal one finds nothing.
std::vector<Candidate> detectLevel(const cv::Mat& img, const cv::Mat& mask, float scale, const OrbOptions& o) {
  std::vector<Candidate> out;
  const int w = img.cols - 2 * kOrbEdge, h = img.rows - 2 * kOrbEdge;  // the region corners may lie in
  // FAST leaves 3 pixels at the border of what it is given: give it 3 more on each side.
  std::vector<cv::KeyPoint> kps;
  cv::FAST(img(cv::Rect(kOrbEdge - 3, kOrbEdge - 3, w + 6, h + 6)), kps, o.fast_threshold, true);
  const int ncx = std::max(1, static_cast<int>(std::lround(double(w) / o.cell_size)));
  const int ncy = std::max(1, static_cast<int>(std::lround(double(h) / o.cell_size)));
  auto cellStart = [](int i, int n, int len) { return kOrbEdge + static_cast<int>(static_cast<long>(i) * len / n); };
  std::vector<int> count(static_cast<size_t>(ncx) * ncy, 0);
  out.reserve(kps.size());
  for (const cv::KeyPoint& k : kps) {
    const int x = static_cast<int>(k.pt.x) + kOrbEdge - 3, y = static_cast<int>(k.pt.y) + kOrbEdge - 3;
    if (!allowed(mask, x * scale, y * scale)) continue;
    out.push_back({x, y, k.response});
    const int cx = std::min(ncx - 1, static_cast<int>(static_cast<long>(x - kOrbEdge) * ncx / w));
    const int cy = std::min(ncy - 1, static_cast<int>(static_cast<long>(y - kOrbEdge) * ncy / h));
    ++count[static_cast<size_t>(cy) * ncx + cx];
  }
  if (o.min_fast_threshold >= o.fast_threshold) return out;
  for (int cy = 0; cy < ncy; ++cy) {
    for (int cx = 0; cx < ncx; ++cx) {
      if (count[static_cast<size_t>(cy) * ncx + cx] > 0) continue;
      const int xa = cellStart(cx, ncx, w), xb = cellStart(cx + 1, ncx, w);
      const int ya = cellStart(cy, ncy, h), yb = cellStart(cy + 1, ncy, h);
      if (xb <= xa || yb <= ya) continue;
      kps.clear();
      cv::FAST(img(cv::Rect(xa - 3, ya - 3, xb - xa + 6, yb - ya + 6)), kps, o.min_fast_threshold, true);
      for (const cv::KeyPoint& k : kps) {
        const int x = static_cast<int>(k.pt.x) + xa - 3, y = static_cast<int>(k.pt.y) + ya - 3;
        if (x < xa || x >= xb || y < ya || y >= yb) continue;
        if (!allowed(mask, x * scale, y * scale)) continue;
        out.push_back({x, y, k.response});
      }
    }
  }
  return out;
}

// Keypoints per level in a geometric series (finer levels cover more area and get more).
std::vector<int> keypointsPerLevel(const OrbOptions& o, size_t levels) {
  const double f = 1.0 / o.scale_factor;
  std::vector<int> wanted(levels);
  const double first = o.num_features * (1 - f) / (1 - std::pow(f, double(levels)));
  int sum = 0;
  for (size_t l = 0; l + 1 < levels; ++l) {
    wanted[l] = static_cast<int>(std::lround(first * std::pow(f, double(l))));
    sum += wanted[l];
  }
  wanted.back() = std::max(0, o.num_features - sum);
  return wanted;
}

}  // namespace

OrbExtraction::OrbExtraction(const cv::Mat& image, const cv::Mat& mask, const OrbOptions& o)
    : options_(o), mask_(mask) {
  o.validate();
  grey_ = toGrey(image);
  if (grey_.empty()) return;
  checkMask(mask, grey_.size());
  if (o.num_features == 0) return;
  scales_ = orbLevelScales(o);
  cv::Mat level = grey_;
  for (size_t l = 0; l < scales_.size(); ++l) {
    if (l > 0) {
      const cv::Size sz(cvRound(grey_.cols / scales_[l]), cvRound(grey_.rows / scales_[l]));
      if (sz.width < 2 * kOrbEdge + 1 || sz.height < 2 * kOrbEdge + 1) break;
      cv::Mat next;
      cv::resize(level, next, sz, 0, 0, cv::INTER_LINEAR_EXACT);  // as cv::ORB builds its pyramid
      level = next;
    } else if (grey_.cols < 2 * kOrbEdge + 1 || grey_.rows < 2 * kOrbEdge + 1) {
      break;
    }
    pyramid_.push_back(level);
  }
  candidates_.resize(pyramid_.size());
}

int OrbExtraction::coarseLevelsStart() const {
  double total = 0;
  for (const cv::Mat& level : pyramid_) total += level.total();
  double coarse = total;
  for (int l = 0; l < levels(); ++l) {
    if (coarse <= 0.5 * total) return l;
    coarse -= pyramid_[static_cast<size_t>(l)].total();
  }
  return levels();
}

void OrbExtraction::detectLevels(int first, int last) {
  for (size_t l = static_cast<size_t>(std::max(first, 0)); l < static_cast<size_t>(std::min(last, levels())); ++l)
    candidates_[l] = detectLevel(pyramid_[l], mask_, scales_[l], options_);
}

void OrbExtraction::finish(std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors, StageTimes* times) {
  keypoints->clear();
  *descriptors = cv::Mat(0, 32, CV_8U);
  if (pyramid_.empty()) return;
  {
    const StageTimer detect_timer(times, Stage::kOrbDetect);
    const std::vector<int> wanted = keypointsPerLevel(options_, scales_.size());
    int carry = 0;  // what a level could not provide goes to the next one
    for (size_t l = 0; l < pyramid_.size(); ++l) {
      const cv::Mat& level = pyramid_[l];
      const std::vector<Candidate>& cand = candidates_[l];
      const int target = wanted[l] + carry;
      const std::vector<int> keep = distributeQuadtree(cand, target, kOrbEdge, kOrbEdge, float(level.cols - kOrbEdge),
                                                       float(level.rows - kOrbEdge));
      carry = target - static_cast<int>(keep.size());
      for (int i : keep) {
        const Candidate& c = cand[static_cast<size_t>(i)];
        keypoints->emplace_back(cv::Point2f(c.x * scales_[l], c.y * scales_[l]), 31.0f * scales_[l],
                                intensityCentroidAngle(level, c.x, c.y), c.response, static_cast<int>(l));
      }
    }
  }
  if (keypoints->empty()) return;

  const StageTimer describe_timer(times, Stage::kOrbDescribe);
  // Descriptors with OpenCV's learned rBRIEF pattern on its own (identically built) pyramid;
  // provided keypoints keep their angle. Their border distance means none is dropped.
  const size_t n = keypoints->size();
  const OrbOptions& o = options_;
  auto orb = cv::ORB::create(o.num_features, o.scale_factor, o.num_levels, kOrbEdge, 0, 2, cv::ORB::FAST_SCORE, 31,
                             o.fast_threshold);
  orb->compute(grey_, *keypoints, *descriptors);
  if (keypoints->size() != n || descriptors->rows != static_cast<int>(n))
    Logger("features").warn(str("ORB descriptor step dropped ", n - keypoints->size(), " of ", n, " keypoints"));
  if (descriptors->empty()) *descriptors = cv::Mat(0, 32, CV_8U);
}

void extractOrb(const cv::Mat& image, const cv::Mat& mask, const OrbOptions& o, std::vector<cv::KeyPoint>* keypoints,
                cv::Mat* descriptors, StageTimes* times) {
  std::optional<StageTimer> detect_timer(std::in_place, times, Stage::kOrbDetect);
  OrbExtraction orb(image, mask, o);
  orb.detectLevels(0, orb.levels());
  detect_timer.reset();
  orb.finish(keypoints, descriptors, times);
}

}  // namespace plslam
