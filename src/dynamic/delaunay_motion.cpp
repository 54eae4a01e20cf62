#include "dynamic/delaunay_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/id_set.h"
#include "core/log.h"
#include "dynamic/delaunay_graph.h"

namespace plslam {

namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // smallest index as root: deterministic
  }
};

/// 1. The graph: correspondences with depth in both frames and the current pixel inside the
/// image, one vertex per pixel position.
DelaunayGraph triangulateCorrespondences(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam) {
  std::vector<cv::Point2f> pixels;
  std::vector<int> index;
  for (int i = 0; i < static_cast<int>(corr.size()); ++i) {
    const auto& c = corr[i];
    if (!c.hasDepthPrev() || !c.hasDepthCur() || !c.uv_cur.allFinite()) continue;
    const cv::Point2f pt(static_cast<float>(c.uv_cur.x()), static_cast<float>(c.uv_cur.y()));
    if (pt.x < 0 || pt.y < 0 || pt.x >= cam.width || pt.y >= cam.height) continue;
    pixels.push_back(pt);
    index.push_back(i);
  }
  return triangulateFeatures(pixels, index, cv::Size(cam.width, cam.height));
}

/// 2. The camera motion: the caller's check, or one run here into `own`.
const MotionCheckResult* referenceMotion(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam,
                                         const DelaunayMotionOptions& o, const MotionCheckResult* motion,
                                         MotionCheckResult* own, DelaunayMotionResult* res) {
  if (motion) {
    if (motion->moving.size() != corr.size())
      throw DataError(str("Delaunay motion: the motion check has ", motion->moving.size(), " flags for ", corr.size(),
                          " correspondences"));
    res->reference_given = true;
  } else {
    *own = checkMotion(corr, cam, o.motion);
    motion = own;
  }
  if (motion->ok()) res->reference = motion->T_cur_prev;
  res->status = res->reference ? DelaunayStatus::kOk : DelaunayStatus::kNoReference;
  return motion;
}

/// 3. Edges: the length test; also each vertex's fraction of broken incident edges.
void testEdges(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam, const DelaunayMotionOptions& o,
               const DelaunayGraph& graph, DelaunayMotionResult* res) {
  const int n_all = static_cast<int>(corr.size());
  const PointNoiseOptions& noise = o.motion.noise;
  std::vector<Eigen::Matrix3d> cov_p(n_all), cov_c(n_all);
  for (int i : graph.vertices) {
    cov_p[i] = pointCovariance(cam, corr[i].uv_prev, corr[i].p_prev.z(), noise, corr[i].pixel_sigma_scale);
    cov_c[i] = pointCovariance(cam, corr[i].uv_cur, corr[i].p_cur.z(), noise, corr[i].pixel_sigma_scale);
  }
  std::vector<int> incident(n_all, 0), broken_incident(n_all, 0);
  for (const auto& [a, b] : graph.edges) {
    DelaunayEdge d;
    d.a = std::min(a, b);
    d.b = std::max(a, b);
    const Eigen::Vector3d vp = corr[d.a].p_prev - corr[d.b].p_prev, vc = corr[d.a].p_cur - corr[d.b].p_cur;
    d.length_prev = vp.norm();
    d.length_cur = vc.norm();
    double var = 0;
    if (d.length_prev > 0) var += vp.dot((cov_p[d.a] + cov_p[d.b]) * vp) / (d.length_prev * d.length_prev);
    if (d.length_cur > 0) var += vc.dot((cov_c[d.a] + cov_c[d.b]) * vc) / (d.length_cur * d.length_cur);
    d.sigma = std::sqrt(var);
    const double change = d.length_cur - d.length_prev;
    d.broken = change * change > o.chi2_length * var;
    res->edges.push_back(d);
    for (int v : {d.a, d.b}) {
      ++incident[v];
      broken_incident[v] += d.broken;
    }
  }
  for (int i : graph.vertices)
    if (incident[i] > 0) res->broken_fraction[i] = static_cast<float>(broken_incident[i]) / incident[i];
}

/// 4 (without a camera motion). The features cut off from the largest group of features that
/// keep their mutual edges (and from any other group that large: the background split by an
/// object). Groups over rigid triangles (three kept edges): single kept edges leak more, as a
/// point moving across an edge keeps its length.
void flagOutsideRigidGroups(const DelaunayMotionOptions& o, const DelaunayGraph& graph, DelaunayMotionResult* res) {
  const std::vector<int>& nodes = graph.vertices;
  UnionFind together(static_cast<int>(res->moving.size()));
  IdSet kept;
  kept.clear(res->edges.size());
  for (const auto& e : res->edges)
    if (!e.broken) kept.insert(undirectedEdgeKey(e.a, e.b));
  auto keptEdge = [&](int a, int b) { return kept.contains(undirectedEdgeKey(a, b)); };
  for (const auto& v : graph.triangles) {
    if (!keptEdge(v[0], v[1]) || !keptEdge(v[1], v[2]) || !keptEdge(v[0], v[2])) continue;
    together.unite(v[0], v[1]);
    together.unite(v[0], v[2]);
  }
  std::vector<int> size_of(res->moving.size());  // per group root
  for (int i : nodes) ++size_of[together.find(i)];
  const int largest = size_of.empty() ? 0 : *std::max_element(size_of.begin(), size_of.end());
  const double static_size = std::min<double>(largest, o.static_group_fraction * nodes.size());
  for (int i : nodes) res->moving[i] = size_of[together.find(i)] < static_size;
}

/// 5. Regions: moving features joined by kept edges on one surface, with their hulls and the
/// Delaunay triangles inside them.
void buildRegions(const std::vector<MotionCorrespondence>& corr, const DelaunayMotionOptions& o,
                  const DelaunayGraph& graph, DelaunayMotionResult* res) {
  UnionFind region(static_cast<int>(corr.size()));
  for (const auto& e : res->edges)
    if (!e.broken && res->moving[e.a] && res->moving[e.b] && o.region_surface.joins(corr[e.a].p_cur.z(), corr[e.b].p_cur.z()))
      region.unite(e.a, e.b);
  std::map<int, std::vector<int>> members_of;
  for (int i : graph.vertices)
    if (res->moving[i]) members_of[region.find(i)].push_back(i);
  std::map<int, size_t> index_of;  // region root -> index in res.regions
  for (auto& [root, members] : members_of) {
    if (static_cast<int>(members.size()) < o.min_region_features) continue;
    MovingRegion r;
    std::vector<cv::Point2f> pts;
    for (int i : members) pts.emplace_back(static_cast<float>(corr[i].uv_cur.x()), static_cast<float>(corr[i].uv_cur.y()));
    cv::convexHull(pts, r.hull);
    r.features = std::move(members);
    index_of[root] = res->regions.size();
    res->regions.push_back(std::move(r));
  }
  if (index_of.empty()) return;
  for (size_t k = 0; k < graph.triangles.size(); ++k) {
    const auto& v = graph.triangles[k];
    if (!res->moving[v[0]] || !res->moving[v[1]] || !res->moving[v[2]]) continue;
    const int root = region.find(v[0]);
    if (region.find(v[1]) != root || region.find(v[2]) != root) continue;
    const auto it = index_of.find(root);
    if (it == index_of.end()) continue;
    res->regions[it->second].triangles.push_back(graph.triangle_pixels[k]);
  }
}

}  // namespace

const char* delaunayStatusName(DelaunayStatus status) {
  switch (status) {
    case DelaunayStatus::kOk: return "ok";
    case DelaunayStatus::kTooFewPoints: return "too_few_points";
    case DelaunayStatus::kNoReference: return "no_reference";
  }
  return "unknown";
}

int DelaunayMotionResult::brokenCount() const {
  return static_cast<int>(std::count_if(edges.begin(), edges.end(), [](const DelaunayEdge& e) { return e.broken; }));
}

int DelaunayMotionResult::movingCount() const { return static_cast<int>(std::count(moving.begin(), moving.end(), 1)); }

DelaunayMotionResult analyseDelaunayMotion(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam,
                                           const DelaunayMotionOptions& o, const MotionCheckResult* motion) {
  const int n_all = static_cast<int>(corr.size());
  DelaunayMotionResult res;
  res.in_graph.assign(n_all, 0);
  res.moving.assign(n_all, 0);
  res.broken_fraction.assign(n_all, std::numeric_limits<float>::quiet_NaN());

  const DelaunayGraph graph = triangulateCorrespondences(corr, cam);
  if (graph.vertices.size() < 3) return res;
  for (int i : graph.vertices) res.in_graph[i] = 1;

  MotionCheckResult own;
  motion = referenceMotion(corr, cam, o, motion, &own, &res);
  testEdges(corr, cam, o, graph, &res);

  // 4. Moving features: the check's flags, or without a camera motion the rigid groups'.
  if (res.reference) {
    for (int i : graph.vertices) res.moving[i] = motion->moving[i];
  } else {
    flagOutsideRigidGroups(o, graph, &res);
  }

  buildRegions(corr, o, graph, &res);
  return res;
}

}  // namespace plslam
