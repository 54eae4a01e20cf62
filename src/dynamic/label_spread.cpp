#include "dynamic/label_spread.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

LabelSpreadResult spreadMotionLabels(const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& depth,
                                     const std::vector<int8_t>& labels, cv::Size size, const LabelSpreadOptions& o) {
  const size_t n = uv.size();
  if (depth.size() != n || labels.size() != n)
    throw DataError(str("label spread: ", n, " pixels, ", depth.size(), " depths and ", labels.size(), " labels"));
  LabelSpreadResult res;
  res.labels = labels;

  // 1. The graph: features with depth inside the image (one vertex per distinct pixel).
  std::map<std::pair<float, float>, int> vertex_of;
  cv::Subdiv2D subdiv(cv::Rect(0, 0, size.width, size.height));
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(depth[i]) || depth[i] <= 0 || !uv[i].allFinite()) continue;
    const cv::Point2f p(static_cast<float>(uv[i].x()), static_cast<float>(uv[i].y()));
    if (p.x < 0 || p.y < 0 || p.x >= size.width || p.y >= size.height) continue;
    if (!vertex_of.emplace(std::make_pair(p.x, p.y), static_cast<int>(i)).second) continue;
    subdiv.insert(p);
  }
  if (vertex_of.size() < 3) return res;
  std::vector<std::vector<int>> neighbours(n);
  std::vector<cv::Vec4f> edges;
  subdiv.getEdgeList(edges);
  for (const auto& e : edges) {
    const auto ia = vertex_of.find({e[0], e[1]}), ib = vertex_of.find({e[2], e[3]});
    if (ia == vertex_of.end() || ib == vertex_of.end()) continue;  // a virtual outer vertex
    const int a = ia->second, b = ib->second;
    if (a == b || std::hypot(e[2] - e[0], e[3] - e[1]) > o.max_edge_px) continue;
    if (!o.surface.joins(depth[a], depth[b])) continue;
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  for (auto& list : neighbours) {  // each edge appears twice in a quad-edge list
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  auto count = [&](const std::vector<int8_t>& l, size_t i, int8_t value) {
    return static_cast<int>(std::count_if(neighbours[i].begin(), neighbours[i].end(), [&](int j) { return l[j] == value; }));
  };

  // 2. Isolated moving features: mismatches.
  for (size_t i = 0; i < n; ++i) {
    if (labels[i] != 1 || count(labels, i, 1) > 0 || count(labels, i, 0) < o.min_still_neighbours) continue;
    res.labels[i] = 0;
    ++res.isolated_cleared;
  }

  // 3. Unjudged features take their judged neighbours' majority, one ring per pass.
  for (int pass = 0; pass < o.passes; ++pass) {
    std::vector<int8_t> next = res.labels;
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      if (res.labels[i] >= 0) continue;
      const int moving = count(res.labels, i, 1), still = count(res.labels, i, 0);
      if (moving == still) continue;
      next[i] = moving > still ? 1 : 0;
      ++(moving > still ? res.spread_moving : res.spread_still);
      changed = true;
    }
    res.labels = std::move(next);
    if (!changed) break;
  }

  // 4. The moving area.
  auto joined = [&](int a, int b) { return std::binary_search(neighbours[a].begin(), neighbours[a].end(), b); };
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  for (const auto& t : triangles) {
    int v[3];
    bool moving = true;
    for (int k = 0; k < 3 && moving; ++k) {
      const auto it = vertex_of.find({t[2 * k], t[2 * k + 1]});
      v[k] = it == vertex_of.end() ? -1 : it->second;
      moving = v[k] >= 0 && res.labels[v[k]] == 1;
    }
    if (moving && joined(v[0], v[1]) && joined(v[1], v[2]) && joined(v[0], v[2]))
      res.moving_triangles.push_back({cv::Point2f(t[0], t[1]), cv::Point2f(t[2], t[3]), cv::Point2f(t[4], t[5])});
  }
  return res;
}

}  // namespace plslam
