// Ray / box intersection in the box's own frame (slab method), shared by the renderer
// and Scene::castRay so both see exactly the same surfaces.
#pragma once

#include <limits>

namespace plslam::synth {

/// Ray o + s*d (box frame) against the box [-h, h]. A solid box reports where the ray
/// enters it, an inward box (the room) where it leaves. Only s > s_min counts.
/// face = axis * 2 + (0: the -h side, 1: the +h side).
/// `s_max`: hits at or beyond it are not wanted (the nearest hit so far), which lets a
/// solid box be rejected early.
inline bool intersectBox(const double o[3], const double d[3], const double h[3], bool inward, double s_min, double* s_hit,
                         int* face, double s_max = std::numeric_limits<double>::infinity()) {
  double tn = -std::numeric_limits<double>::infinity(), tf = std::numeric_limits<double>::infinity();
  int an = -1, af = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (o[i] < -h[i] || o[i] > h[i]) return false;
      continue;
    }
    const double inv = 1.0 / d[i];
    double t0 = (-h[i] - o[i]) * inv, t1 = (h[i] - o[i]) * inv;
    if (t0 > t1) {
      const double tmp = t0;
      t0 = t1;
      t1 = tmp;
    }
    if (t0 > tn) {
      tn = t0;
      an = i;
    }
    if (t1 < tf) {
      tf = t1;
      af = i;
    }
    if (!inward && (tn > tf || tn >= s_max || tf <= s_min)) return false;
  }
  if (tn > tf) return false;
  if (!inward) {
    if (an < 0 || tn <= s_min || tn >= s_max) return false;
    *s_hit = tn;
    *face = an * 2 + (d[an] > 0 ? 0 : 1);
  } else {
    if (af < 0 || tf <= s_min || tf >= s_max) return false;
    *s_hit = tf;
    *face = af * 2 + (d[af] > 0 ? 1 : 0);
  }
  return true;
}

}  // namespace plslam::synth
