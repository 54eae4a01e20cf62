#include "dynamic/delaunay_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <unordered_set>

#include "core/error.h"
#include "core/log.h"

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

int64_t edgeKey(int a, int b) { return (static_cast<int64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b)); }

/// Current pixel -> correspondence, for mapping the subdivision's vertices back.
using VertexMap = std::map<std::pair<float, float>, int>;

int lookup(const VertexMap& vertex_of, float x, float y) {
  const auto it = vertex_of.find({x, y});
  return it == vertex_of.end() ? -1 : it->second;
}

/// 1. Vertices: depth in both frames, current pixel inside the image, one per pixel position.
std::vector<int> collectVertices(const std::vector<MotionCorrespondence>& corr, const PinholeCamera& cam,
                                 VertexMap* vertex_of) {
  std::vector<int> nodes;
  for (int i = 0; i < static_cast<int>(corr.size()); ++i) {
    const auto& c = corr[i];
    if (!c.hasDepthPrev() || !c.hasDepthCur() || !c.uv_cur.allFinite()) continue;
    const cv::Point2f pt(static_cast<float>(c.uv_cur.x()), static_cast<float>(c.uv_cur.y()));
    if (pt.x < 0 || pt.y < 0 || pt.x >= cam.width || pt.y >= cam.height) continue;
    if (!vertex_of->emplace(std::make_pair(pt.x, pt.y), i).second) continue;
    nodes.push_back(i);
  }
  return nodes;
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
               const std::vector<int>& nodes, cv::Subdiv2D& subdiv, const VertexMap& vertex_of,
               DelaunayMotionResult* res) {
  const int n_all = static_cast<int>(corr.size());
  const PointNoiseOptions& noise = o.motion.noise;
  std::vector<Eigen::Matrix3d> cov_p(n_all), cov_c(n_all);
  for (int i : nodes) {
    cov_p[i] = pointCovariance(cam, corr[i].uv_prev, corr[i].p_prev.z(), noise, corr[i].pixel_sigma_scale);
    cov_c[i] = pointCovariance(cam, corr[i].uv_cur, corr[i].p_cur.z(), noise, corr[i].pixel_sigma_scale);
  }
  std::vector<cv::Vec4f> edge_list;
  subdiv.getEdgeList(edge_list);
  std::unordered_set<int64_t> seen;
  std::vector<int> incident(n_all, 0), broken_incident(n_all, 0);
  for (const auto& e : edge_list) {
    const int a = lookup(vertex_of, e[0], e[1]), b = lookup(vertex_of, e[2], e[3]);  // -1: a virtual outer vertex
    if (a < 0 || b < 0 || a == b || !seen.insert(edgeKey(a, b)).second) continue;
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
  for (int i : nodes)
    if (incident[i] > 0) res->broken_fraction[i] = static_cast<float>(broken_incident[i]) / incident[i];
}

/// 4 (without a camera motion). The features cut off from the largest group of features that
/// keep their mutual edges (and from any other group that large: the background split by an
/// object). Groups over rigid triangles (three kept edges): single kept edges leak more, as a
/// point moving across an edge keeps its length.
void flagOutsideRigidGroups(const DelaunayMotionOptions& o, const std::vector<int>& nodes, cv::Subdiv2D& subdiv,
                            const VertexMap& vertex_of, DelaunayMotionResult* res) {
  UnionFind together(static_cast<int>(res->moving.size()));
  std::unordered_set<int64_t> kept;
  for (const auto& e : res->edges)
    if (!e.broken) kept.insert(edgeKey(e.a, e.b));
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  for (const auto& t : triangles) {
    const int v[3] = {lookup(vertex_of, t[0], t[1]), lookup(vertex_of, t[2], t[3]), lookup(vertex_of, t[4], t[5])};
    if (v[0] < 0 || v[1] < 0 || v[2] < 0) continue;
    if (!kept.count(edgeKey(v[0], v[1])) || !kept.count(edgeKey(v[1], v[2])) || !kept.count(edgeKey(v[0], v[2]))) continue;
    together.unite(v[0], v[1]);
    together.unite(v[0], v[2]);
  }
  std::map<int, int> size_of;
  for (int i : nodes) ++size_of[together.find(i)];
  int largest = 0;
  for (const auto& [root, size] : size_of) largest = std::max(largest, size);
  const double static_size = std::min<double>(largest, o.static_group_fraction * nodes.size());
  for (int i : nodes) res->moving[i] = size_of[together.find(i)] < static_size;
}

/// 5. Regions: moving features joined by kept edges on one surface, with their hulls and the
/// Delaunay triangles inside them.
void buildRegions(const std::vector<MotionCorrespondence>& corr, const DelaunayMotionOptions& o,
                  const std::vector<int>& nodes, cv::Subdiv2D& subdiv, const VertexMap& vertex_of,
                  DelaunayMotionResult* res) {
  UnionFind region(static_cast<int>(corr.size()));
  for (const auto& e : res->edges)
    if (!e.broken && res->moving[e.a] && res->moving[e.b] && o.region_surface.joins(corr[e.a].p_cur.z(), corr[e.b].p_cur.z()))
      region.unite(e.a, e.b);
  std::map<int, std::vector<int>> members_of;
  for (int i : nodes)
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
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  for (const auto& t : triangles) {
    const int v[3] = {lookup(vertex_of, t[0], t[1]), lookup(vertex_of, t[2], t[3]), lookup(vertex_of, t[4], t[5])};
    if (v[0] < 0 || v[1] < 0 || v[2] < 0 || !res->moving[v[0]] || !res->moving[v[1]] || !res->moving[v[2]]) continue;
    const int root = region.find(v[0]);
    if (region.find(v[1]) != root || region.find(v[2]) != root) continue;
    const auto it = index_of.find(root);
    if (it == index_of.end()) continue;
    res->regions[it->second].triangles.push_back({cv::Point2f(t[0], t[1]), cv::Point2f(t[2], t[3]), cv::Point2f(t[4], t[5])});
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

  VertexMap vertex_of;
  const std::vector<int> nodes = collectVertices(corr, cam, &vertex_of);
  if (nodes.size() < 3) return res;
  cv::Subdiv2D subdiv(cv::Rect(0, 0, cam.width, cam.height));
  for (int i : nodes) {
    res.in_graph[i] = 1;
    subdiv.insert(cv::Point2f(static_cast<float>(corr[i].uv_cur.x()), static_cast<float>(corr[i].uv_cur.y())));
  }

  MotionCheckResult own;
  motion = referenceMotion(corr, cam, o, motion, &own, &res);
  testEdges(corr, cam, o, nodes, subdiv, vertex_of, &res);

  // 4. Moving features: the check's flags, or without a camera motion the rigid groups'.
  if (res.reference) {
    for (int i : nodes) res.moving[i] = motion->moving[i];
  } else {
    flagOutsideRigidGroups(o, nodes, subdiv, vertex_of, &res);
  }

  buildRegions(corr, o, nodes, subdiv, vertex_of, &res);
  return res;
}

}  // namespace plslam
