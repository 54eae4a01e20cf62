#include "dynamic/delaunay_graph.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <limits>
#include <utility>

#include "core/error.h"
#include "core/id_set.h"
#include "core/log.h"

namespace plslam {

namespace {
/// A pixel's two floats as one key (the coordinates Subdiv2D returns are the ones inserted).
uint64_t pixelKey(float x, float y) {
  uint32_t bx = 0, by = 0;
  std::memcpy(&bx, &x, sizeof bx);
  std::memcpy(&by, &y, sizeof by);
  return (static_cast<uint64_t>(bx) << 32) | by;
}
// Subdiv2D finds each new point's triangle by walking from the last one inserted, so points
// given in a snake over bands of rows keep each walk short (the order ORB returns keypoints
// in, level by level, jumps across the image).
std::vector<int> snakeOrder(const std::vector<cv::Point2f>& points) {
  constexpr float kBandPx = 32.0f;
  std::vector<int> order(points.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  auto band = [&](int k) { return static_cast<int>(points[k].y / kBandPx); };
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const int ba = band(a), bb = band(b);
    if (ba != bb) return ba < bb;
    if (points[a].x != points[b].x) return (ba % 2 == 0) == (points[a].x < points[b].x);
    return a < b;
  });
  return order;
}

/// The index given with each distinct pixel (the first one given there), found by binary
/// search in one sorted array: the dynamic check builds this on every frame, and a hash map
/// allocated a node per keypoint (docs/RESULTS.md, "The long run's growing search").
class PixelIndex {
 public:
  PixelIndex(const std::vector<cv::Point2f>& pixels, const std::vector<int>& index) : first_(pixels.size()) {
    std::vector<std::pair<uint64_t, size_t>> keyed(pixels.size());
    for (size_t k = 0; k < pixels.size(); ++k) keyed[k] = {pixelKey(pixels[k].x, pixels[k].y), k};
    std::sort(keyed.begin(), keyed.end());  // by key, then by position: the first given comes first
    for (size_t k = 0; k < keyed.size(); ++k) {
      if (k > 0 && keyed[k].first == keyed[k - 1].first) continue;
      first_[keyed[k].second] = 1;
      sorted_.push_back({keyed[k].first, index[keyed[k].second]});
    }
  }
  /// Whether pixels[k] is the first of the pixels at its place.
  bool isFirstAt(size_t k) const { return first_[k] != 0; }
  /// The index given at (x, y), or -1 (no pixel given there: a virtual outer vertex).
  int find(float x, float y) const {
    const uint64_t key = pixelKey(x, y);
    const auto it =
        std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(key, std::numeric_limits<int>::min()));
    return it != sorted_.end() && it->first == key ? it->second : -1;
  }

 private:
  std::vector<char> first_;
  std::vector<std::pair<uint64_t, int>> sorted_;
};

}  // namespace

DelaunayGraph triangulateFeatures(const std::vector<cv::Point2f>& pixels, const std::vector<int>& index,
                                  cv::Size image) {
  if (pixels.size() != index.size())
    throw DataError(str("Delaunay graph: ", pixels.size(), " pixels and ", index.size(), " indices"));
  DelaunayGraph g;
  const PixelIndex index_at(pixels, index);
  std::vector<cv::Point2f> distinct;
  for (size_t k = 0; k < pixels.size(); ++k) {
    if (!index_at.isFirstAt(k)) continue;
    g.vertices.push_back(index[k]);
    distinct.push_back(pixels[k]);
  }
  if (g.vertices.size() < 3) return g;
  cv::Subdiv2D subdiv(cv::Rect(0, 0, image.width, image.height));
  for (int k : snakeOrder(distinct)) subdiv.insert(distinct[k]);

  std::vector<cv::Vec4f> edge_list;
  subdiv.getEdgeList(edge_list);
  IdSet seen;
  seen.clear(edge_list.size());
  for (const cv::Vec4f& e : edge_list) {
    const int a = index_at.find(e[0], e[1]), b = index_at.find(e[2], e[3]);
    if (a < 0 || b < 0 || a == b || !seen.insert(undirectedEdgeKey(a, b))) continue;
    g.edges.push_back({a, b});
  }
  std::vector<cv::Vec6f> triangle_list;
  subdiv.getTriangleList(triangle_list);
  for (const cv::Vec6f& t : triangle_list) {
    const std::array<int, 3> v = {index_at.find(t[0], t[1]), index_at.find(t[2], t[3]), index_at.find(t[4], t[5])};
    if (v[0] < 0 || v[1] < 0 || v[2] < 0) continue;
    g.triangles.push_back(v);
    g.triangle_pixels.push_back({cv::Point2f(t[0], t[1]), cv::Point2f(t[2], t[3]), cv::Point2f(t[4], t[5])});
  }
  return g;
}

}  // namespace plslam
