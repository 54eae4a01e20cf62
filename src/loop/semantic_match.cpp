#include "loop/semantic_match.h"

#include <algorithm>
#include <cmath>

namespace plslam {

namespace {
bool usable(const KeyframeInstance& i) { return !i.dynamic && i.centroid_c.allFinite() && i.class_id >= 0; }
Eigen::Vector2d centre(const cv::Rect& r) { return {r.x + 0.5 * r.width, r.y + 0.5 * r.height}; }
}  // namespace

SemanticResult matchInstances(const std::vector<KeyframeInstance>& a, const std::vector<KeyframeInstance>& b,
                              double image_diagonal, const SemanticOptions& o, const std::optional<SE3>& T_a_b) {
  SemanticResult r;
  for (const auto& i : a) r.static_a += usable(i);
  for (const auto& i : b) r.static_b += usable(i);

  // Candidate pairs: same class, close boxes, similar depth; one-to-one, closest first.
  struct Pair {
    int a, b;
    double offset;
  };
  std::vector<Pair> pairs;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!usable(a[i])) continue;
    for (size_t j = 0; j < b.size(); ++j) {
      if (!usable(b[j]) || a[i].class_id != b[j].class_id) continue;
      const double offset = (centre(a[i].box) - centre(b[j].box)).norm() / std::max(1.0, image_diagonal);
      if (offset > o.max_image_offset) continue;
      if (std::fabs(a[i].centroid_c.z() - b[j].centroid_c.z()) > o.max_depth_difference_m) continue;
      if (T_a_b && (a[i].centroid_c - *T_a_b * b[j].centroid_c).norm() > o.max_position_error_m) continue;
      pairs.push_back({static_cast<int>(i), static_cast<int>(j), offset});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
    return x.offset < y.offset || (x.offset == y.offset && (x.a < y.a || (x.a == y.a && x.b < y.b)));
  });
  std::vector<char> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<InstanceMatch> candidates;
  for (const Pair& p : pairs) {
    if (used_a[p.a] || used_b[p.b]) continue;
    used_a[p.a] = used_b[p.b] = 1;
    candidates.push_back({p.a, p.b});
  }

  if (T_a_b || candidates.size() < 2) {
    r.matches = candidates;
  } else {
    // Largest set whose pairwise distances agree: seed with each match, add the ones
    // consistent with every member so far.
    for (size_t s = 0; s < candidates.size(); ++s) {
      std::vector<InstanceMatch> set{candidates[s]};
      for (size_t t = 0; t < candidates.size(); ++t) {
        if (t == s) continue;
        bool ok = true;
        for (const InstanceMatch& m : set) {
          const double da = (a[candidates[t].a].centroid_c - a[m.a].centroid_c).norm();
          const double db = (b[candidates[t].b].centroid_c - b[m.b].centroid_c).norm();
          if (std::fabs(da - db) > o.max_position_error_m) ok = false;
        }
        if (ok) set.push_back(candidates[t]);
      }
      if (set.size() > r.matches.size()) r.matches = set;
    }
  }

  double weight = 0;
  for (const InstanceMatch& m : r.matches) {
    const bool generic = std::find(o.generic_classes.begin(), o.generic_classes.end(), a[m.a].class_name) !=
                         o.generic_classes.end();
    weight += generic ? o.generic_weight : 1.0;
  }
  const int most = std::max(r.static_a, r.static_b);
  r.similarity = most > 0 ? std::min(1.0, weight / most) : 0.0;
  if (static_cast<int>(r.matches.size()) >= o.min_matches) {
    r.factor = 1.0 + o.gain * r.similarity;
  } else if (r.matches.empty() && r.static_a >= o.min_instances_to_refute && r.static_b >= o.min_instances_to_refute) {
    r.refuted = true;
    r.factor = 1.0 - o.penalty;
  }
  return r;
}

}  // namespace plslam
