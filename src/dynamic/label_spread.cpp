#include "dynamic/label_spread.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"
#include "dynamic/delaunay_graph.h"

namespace plslam {

// Step 1: one vertex per distinct pixel (triangulateFeatures); the edges are counted as the
// header says and sorted per feature, for the binary search of step 4.
SurfaceGraph buildSurfaceGraph(const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& depth,
                               cv::Size size, const LabelSpreadOptions& o) {
  if (depth.size() != uv.size())
    throw DataError(str("surface graph: ", uv.size(), " pixels and ", depth.size(), " depths"));
  std::vector<cv::Point2f> pixels;
  std::vector<int> index;
  for (size_t i = 0; i < uv.size(); ++i) {
    if (!std::isfinite(depth[i]) || depth[i] <= 0 || !uv[i].allFinite()) continue;
    const cv::Point2f p(static_cast<float>(uv[i].x()), static_cast<float>(uv[i].y()));
    if (p.x < 0 || p.y < 0 || p.x >= size.width || p.y >= size.height) continue;
    pixels.push_back(p);
    index.push_back(static_cast<int>(i));
  }
  SurfaceGraph g;
  g.graph = triangulateFeatures(pixels, index, size);
  g.neighbours.resize(uv.size());
  for (const auto& [a, b] : g.graph.edges) {
    const cv::Point2f pa(static_cast<float>(uv[a].x()), static_cast<float>(uv[a].y()));
    const cv::Point2f pb(static_cast<float>(uv[b].x()), static_cast<float>(uv[b].y()));
    if (std::hypot(pb.x - pa.x, pb.y - pa.y) > o.max_edge_px) continue;
    if (!o.surface.joins(depth[a], depth[b])) continue;
    g.neighbours[a].push_back(b);
    g.neighbours[b].push_back(a);
  }
  for (auto& list : g.neighbours) std::sort(list.begin(), list.end());
  return g;
}

LabelSpreadResult spreadMotionLabels(const SurfaceGraph& surface, const std::vector<int8_t>& labels,
                                     const LabelSpreadOptions& o) {
  const std::vector<std::vector<int>>& neighbours = surface.neighbours;
  const size_t n = neighbours.size();
  if (labels.size() != n) throw DataError(str("label spread: ", n, " features and ", labels.size(), " labels"));
  LabelSpreadResult res;
  res.labels = labels;
  const DelaunayGraph& graph = surface.graph;
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
  for (size_t k = 0; k < graph.triangles.size(); ++k) {
    const auto& v = graph.triangles[k];
    if (res.labels[v[0]] == 1 && res.labels[v[1]] == 1 && res.labels[v[2]] == 1 && joined(v[0], v[1]) &&
        joined(v[1], v[2]) && joined(v[0], v[2]))
      res.moving_triangles.push_back(graph.triangle_pixels[k]);
  }
  return res;
}

int floodMovingLabels(const SurfaceGraph& surface, std::vector<int> seeds, std::vector<int8_t>* labels) {
  const std::vector<std::vector<int>>& neighbours = surface.neighbours;
  if (labels->size() != neighbours.size())
    throw DataError(str("label flood: ", neighbours.size(), " features and ", labels->size(), " labels"));
  int flooded = 0;
  while (!seeds.empty()) {
    const int k = seeds.back();
    seeds.pop_back();
    for (int j : neighbours[k])
      if ((*labels)[j] < 0) {
        (*labels)[j] = 1;
        seeds.push_back(j);
        ++flooded;
      }
  }
  return flooded;
}

}  // namespace plslam
