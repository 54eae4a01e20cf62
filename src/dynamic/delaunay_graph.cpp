#include "dynamic/delaunay_graph.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <unordered_map>
#include <unordered_set>

#include "core/error.h"
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

}  // namespace

DelaunayGraph triangulateFeatures(const std::vector<cv::Point2f>& pixels, const std::vector<int>& index,
                                  cv::Size image) {
  if (pixels.size() != index.size())
    throw DataError(str("Delaunay graph: ", pixels.size(), " pixels and ", index.size(), " indices"));
  DelaunayGraph g;
  std::unordered_map<uint64_t, int> index_at;
  index_at.reserve(pixels.size());
  std::vector<cv::Point2f> distinct;
  for (size_t k = 0; k < pixels.size(); ++k) {
    if (!index_at.emplace(pixelKey(pixels[k].x, pixels[k].y), index[k]).second) continue;
    g.vertices.push_back(index[k]);
    distinct.push_back(pixels[k]);
  }
  if (g.vertices.size() < 3) return g;
  cv::Subdiv2D subdiv(cv::Rect(0, 0, image.width, image.height));
  for (int k : snakeOrder(distinct)) subdiv.insert(distinct[k]);
  auto lookup = [&](float x, float y) {
    const auto it = index_at.find(pixelKey(x, y));
    return it == index_at.end() ? -1 : it->second;  // -1: a virtual outer vertex
  };

  std::vector<cv::Vec4f> edge_list;
  subdiv.getEdgeList(edge_list);
  std::unordered_set<int64_t> seen;
  for (const cv::Vec4f& e : edge_list) {
    const int a = lookup(e[0], e[1]), b = lookup(e[2], e[3]);
    if (a < 0 || b < 0 || a == b || !seen.insert(undirectedEdgeKey(a, b)).second) continue;
    g.edges.push_back({a, b});
  }
  std::vector<cv::Vec6f> triangle_list;
  subdiv.getTriangleList(triangle_list);
  for (const cv::Vec6f& t : triangle_list) {
    const std::array<int, 3> v = {lookup(t[0], t[1]), lookup(t[2], t[3]), lookup(t[4], t[5])};
    if (v[0] < 0 || v[1] < 0 || v[2] < 0) continue;
    g.triangles.push_back(v);
    g.triangle_pixels.push_back({cv::Point2f(t[0], t[1]), cv::Point2f(t[2], t[3]), cv::Point2f(t[4], t[5])});
  }
  return g;
}

}  // namespace plslam
