#include "synth/texture.h"

#include <algorithm>
#include <cmath>

#include "synth/hash.h"

namespace plslam::synth {

namespace {

struct Style {
  double min_cell;     ///< smallest leaf side, metres
  double max_cell;     ///< cells larger than this always split
  double stop_prob;    ///< chance that a cell between the two sizes stays a leaf
  double grout_width;  ///< width of drawn split lines, metres
  double grout_prob;   ///< chance that a split line is drawn
  float grout_val;     ///< grey level of the split lines
  double hue0, hue_span;  ///< hue range, degrees; hue0 < 0: hue taken from the seed
  double sat_lo, sat_hi, val_lo, val_hi;
  // Leaf pattern probabilities (the rest are plain).
  double p_stripes, p_diagonal, p_frame, p_text, p_tiles;
};

const Style& style(Material m) {
  static const Style kStyles[] = {
      /* wall      */ {0.22, 1.20, 0.45, 0.016, 0.30, 0.10f, 0, 360, 0.05, 0.45, 0.45, 0.95, 0.05, 0.04, 0.16, 0.07, 0.04},
      /* floor     */ {0.25, 0.90, 0.30, 0.012, 0.70, 0.12f, 15, 30, 0.25, 0.60, 0.25, 0.65, 0.08, 0.00, 0.05, 0.00, 0.04},
      /* ceiling   */ {0.35, 1.20, 0.30, 0.020, 0.80, 0.35f, 30, 40, 0.00, 0.12, 0.65, 0.95, 0.05, 0.00, 0.10, 0.00, 0.03},
      /* wood      */ {0.08, 0.35, 0.30, 0.008, 0.50, 0.12f, 15, 30, 0.30, 0.70, 0.20, 0.70, 0.25, 0.05, 0.10, 0.00, 0.05},
      /* cardboard */ {0.06, 0.30, 0.30, 0.008, 0.30, 0.15f, 25, 20, 0.35, 0.60, 0.40, 0.80, 0.05, 0.05, 0.20, 0.25, 0.10},
      /* poster    */ {0.04, 0.25, 0.25, 0.010, 0.40, 0.05f, 0, 360, 0.30, 0.90, 0.20, 0.95, 0.10, 0.10, 0.20, 0.20, 0.10},
      /* shirt     */ {0.05, 0.25, 0.30, 0.008, 0.30, 0.10f, -1, 50, 0.40, 0.90, 0.30, 0.90, 0.30, 0.10, 0.10, 0.00, 0.05},
      /* trousers  */ {0.08, 0.30, 0.40, 0.006, 0.60, 0.05f, 210, 40, 0.20, 0.60, 0.12, 0.45, 0.10, 0.00, 0.10, 0.00, 0.00},
      /* skin      */ {0.04, 0.12, 0.40, 0.000, 0.00, 0.00f, 15, 20, 0.30, 0.55, 0.45, 0.85, 0.00, 0.00, 0.15, 0.00, 0.00},
      /* hair      */ {0.04, 0.12, 0.50, 0.000, 0.00, 0.00f, 20, 20, 0.30, 0.60, 0.05, 0.30, 0.20, 0.00, 0.00, 0.00, 0.00},
  };
  return kStyles[static_cast<int>(m)];
}

/// One mix per call: cheap enough to run for every level of every texel.
inline uint64_t h64(uint64_t a, uint64_t b) { return mix64(a ^ (b * 0x9E3779B97F4A7C15ULL)); }
/// Bits [shift, shift + 16) of h as a value in [0, 1).
inline double bits16(uint64_t h, int shift) { return static_cast<double>((h >> shift) & 0xffff) * (1.0 / 65536.0); }

Rgb hsv(double hue_deg, double s, double v) {
  double h = hue_deg * (1.0 / 60.0);
  h -= 6.0 * std::floor(h / 6.0);
  const int i = std::min(5, static_cast<int>(h));
  const double f = h - i;
  const float p = static_cast<float>(v * (1 - s)), q = static_cast<float>(v * (1 - s * f)),
              t = static_cast<float>(v * (1 - s * (1 - f))), vv = static_cast<float>(v);
  switch (i) {
    case 0: return {vv, t, p};
    case 1: return {q, vv, p};
    case 2: return {p, vv, t};
    case 3: return {p, q, vv};
    case 4: return {t, p, vv};
    default: return {vv, p, q};
  }
}

struct Palette {
  Rgb c0, c1;  // a colour and one that contrasts with it
};

Palette palette(const Style& st, double seed_hue, uint64_t h) {
  const double hue0 = st.hue0 < 0 ? seed_hue : st.hue0;
  const double hue = hue0 + st.hue_span * bits16(h, 0);
  const double sat = st.sat_lo + (st.sat_hi - st.sat_lo) * bits16(h, 16);
  const double val = st.val_lo + (st.val_hi - st.val_lo) * bits16(h, 32);
  // The second colour differs in brightness by at least 0.3 so that its edges are strong.
  const double mid = 0.5 * (st.val_lo + st.val_hi);
  const double dv = 0.3 + 0.3 * static_cast<double>((h >> 48) & 0xff) / 256.0;
  const double val1 = std::clamp(val < mid ? val + dv : val - dv, 0.05, 0.98);
  const double hue1 = hue + st.hue_span * (static_cast<double>((h >> 56) & 0x7f) / 128.0 - 0.5) + ((h >> 63) ? 180 : 0);
  return {hsv(hue, sat, val), hsv(hue1, std::min(1.0, sat * 1.2), val1)};
}

enum class Pattern { kPlain, kStripes, kDiagonal, kFrame, kText, kTiles };

/// The pattern of a leaf of w x h metres whose pattern hash is hp.
Pattern leafPattern(const Style& st, uint64_t hp, double w, double h, bool allow_frame) {
  const double small = std::min(w, h);
  // Large cells stay plain or framed: wall-sized stripes would be a repetitive pattern.
  const bool large = std::max(w, h) > 0.8;
  double u = bits16(hp, 0);
  auto pick = [&u](double p) {
    if (u < p) return true;
    u -= p;
    return false;
  };
  if (pick(st.p_stripes)) return small > 0.06 && !large ? Pattern::kStripes : Pattern::kPlain;
  if (pick(st.p_diagonal)) return small > 0.08 && !large ? Pattern::kDiagonal : Pattern::kPlain;
  if (pick(st.p_frame)) return allow_frame && small > 0.1 ? Pattern::kFrame : Pattern::kPlain;
  if (pick(st.p_text)) return small > 0.08 && !large ? Pattern::kText : Pattern::kPlain;
  if (pick(st.p_tiles)) return small > 0.1 && !large ? Pattern::kTiles : Pattern::kPlain;
  return Pattern::kPlain;
}

/// One leaf rectangle [x0,x1]x[y0,y1] containing (s, t).
Rgb leafColour(const Style& st, double seed_hue, uint64_t h, const Palette& pal, double s, double t, double x0, double x1,
               double y0, double y1, bool allow_frame) {
  const uint64_t hp = h64(h, 0x77);  // pattern parameters
  const double small = std::min(x1 - x0, y1 - y0);
  const Pattern pattern = leafPattern(st, hp, x1 - x0, y1 - y0, allow_frame);
  if (pattern == Pattern::kStripes) {
    const double period = 0.03 + 0.09 * bits16(hp, 16);
    const double duty = 0.35 + 0.3 * bits16(hp, 32);
    const double c = ((hp >> 48) & 1) ? (s - x0) : (t - y0);
    const double f = c / period - std::floor(c / period);
    return f < duty ? pal.c1 : pal.c0;
  }
  if (pattern == Pattern::kDiagonal) {
    const double a = (15.0 + 60.0 * bits16(hp, 16)) * M_PI / 180.0 + (((hp >> 48) & 1) ? M_PI / 2 : 0);
    const double period = 0.05 + 0.09 * bits16(hp, 32);
    const double c = ((s - x0) * std::cos(a) + (t - y0) * std::sin(a)) / period;
    return c - std::floor(c) < 0.5 ? pal.c1 : pal.c0;
  }
  if (pattern == Pattern::kFrame) {
    const double m = small * (0.08 + 0.15 * bits16(hp, 16));
    if (s < x0 + m || s > x1 - m || t < y0 + m || t > y1 - m) return pal.c0;
    const uint64_t inner = h64(h, 18);
    return leafColour(st, seed_hue, inner, palette(st, seed_hue, inner), s, t, x0 + m, x1 - m, y0 + m, y1 - m, false);
  }
  if (pattern == Pattern::kText) {
    // Rows of "words": dark blocks on a light page.
    const Rgb paper = hsv(40, 0.05 + 0.1 * bits16(hp, 16), 0.85 + 0.1 * bits16(hp, 32));
    const double margin = 0.1 * small;
    if (s < x0 + margin || s > x1 - margin || t < y0 + margin || t > y1 - margin) return paper;
    const double pitch = 0.03 + 0.02 * bits16(hp, 48);
    const double ink_h = pitch * 0.55;
    const double ty = t - (y0 + margin);
    const long row = static_cast<long>(std::floor(ty / pitch));
    if (ty - row * pitch > ink_h) return paper;
    const Rgb ink = pal.c0.r + pal.c0.g + pal.c0.b < 1.2f ? pal.c0 : Rgb{0.1f, 0.1f, 0.12f};
    double x = x0 + margin;
    for (int k = 0; k < 64; ++k) {
      const uint64_t wh = h64(h64(h, static_cast<uint64_t>(row)), static_cast<uint64_t>(k));
      const double len = 0.02 + 0.08 * bits16(wh, 0);
      const double gap = 0.012 + 0.013 * bits16(wh, 16);
      if (s < x) return paper;
      if (s <= x + len) return x + len > x1 - margin ? paper : ink;
      x += len + gap;
      if (x > x1 - margin) return paper;
    }
    return paper;
  }
  if (pattern == Pattern::kTiles) {
    const double c = 0.03 + 0.04 * bits16(hp, 16);
    const auto i = static_cast<int64_t>(std::floor((s - x0) / c)), j = static_cast<int64_t>(std::floor((t - y0) / c));
    return (h64(h64(h, static_cast<uint64_t>(i)), static_cast<uint64_t>(j)) & 1) ? pal.c1 : pal.c0;
  }
  return pal.c0;
}

}  // namespace

const char* materialName(Material m) {
  static const char* kNames[] = {"wall", "floor", "ceiling", "wood", "cardboard", "poster", "shirt", "trousers", "skin", "hair"};
  return kNames[static_cast<int>(m)];
}

FaceTexture::FaceTexture(Material m, uint64_t seed, double w, double h)
    : material_(m), base_(h64(seed, static_cast<uint64_t>(m) + 1)),
      seed_hue_(360.0 * bits16(mix64(seed ^ 0x5eed), 0)) {
  nodes_.reserve(64);
  nodes_.emplace_back();
  build(0, 0, w, 0, h, 1, 0);
  half_grout_ = 0.5 * style(m).grout_width;
  buildGrid(w, h);
}

void FaceTexture::buildGrid(double w, double h) {
  const double cell = std::max(style(material_).min_cell, std::max(w, h) / 256.0);
  cell_inv_ = 1.0 / cell;
  grid_w_ = std::max(1, static_cast<int>(std::ceil(w * cell_inv_)));
  grid_h_ = std::max(1, static_cast<int>(std::ceil(h * cell_inv_)));
  grid_.resize(static_cast<size_t>(grid_w_) * grid_h_);
  const double eps = 1e-9;  // covers rounding in the lookup's cell index
  for (int j = 0; j < grid_h_; ++j)
    for (int i = 0; i < grid_w_; ++i) {
      const double cx0 = i * cell - eps, cx1 = (i + 1) * cell + eps, cy0 = j * cell - eps, cy1 = (j + 1) * cell + eps;
      int n = 0;
      // Descend while the whole cell is on one side of the split and clear of its grout.
      while (nodes_[n].child >= 0) {
        const Node& nd = nodes_[n];
        const double lo = nd.split_x ? cx0 : cy0, hi = nd.split_x ? cx1 : cy1;
        const double g = nd.grout ? half_grout_ : 0.0;
        if (hi <= nd.pos - g) n = nd.child;
        else if (lo >= nd.pos + g) n = nd.child + 1;
        else break;
      }
      grid_[static_cast<size_t>(j) * grid_w_ + i] = n;
    }
}

/// Fills nodes_[index] for the cell [x0,x1]x[y0,y1] (node: its id in the implicit binary
/// tree, which seeds its random choices), then its children, appended at the end.
void FaceTexture::build(int index, double x0, double x1, double y0, double y1, uint64_t node, int depth) {
  const Style& st = style(material_);
  const uint64_t hn = h64(base_, node);  // bits: 0-15 stop, 16 axis, 17-32 split position, 33-48 grout
  const double cw = x1 - x0, ch = y1 - y0;
  const double big = std::max(cw, ch);
  const bool leaf = depth >= 40 || big < 2 * st.min_cell || (big < st.max_cell && bits16(hn, 0) < st.stop_prob);
  if (leaf) {
    const uint64_t lh = h64(base_, node ^ 0xabcdef);
    const Palette pal = palette(st, seed_hue_, lh);
    const bool plain = leafPattern(st, h64(lh, 0x77), cw, ch, true) == Pattern::kPlain;
    nodes_[index].leaf = static_cast<int>(leaves_.size());
    leaves_.push_back({x0, x1, y0, y1, lh, pal.c0, pal.c1, plain});
    return;
  }
  bool split_x;
  if (cw > 1.5 * ch) split_x = true;
  else if (ch > 1.5 * cw) split_x = false;
  else split_x = (hn >> 16) & 1;
  if (split_x && cw < 2 * st.min_cell) split_x = false;
  if (!split_x && ch < 2 * st.min_cell) split_x = true;
  const double lo = split_x ? x0 : y0, len = split_x ? cw : ch;
  double pos = lo + len * (0.25 + 0.5 * bits16(hn, 17));
  pos = std::clamp(pos, lo + st.min_cell, lo + len - st.min_cell);
  const int child = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  Node& n = nodes_[index];
  n.pos = pos;
  n.split_x = split_x;
  n.grout = st.grout_width > 0 && bits16(hn, 33) < st.grout_prob;
  n.child = child;
  if (split_x) {
    build(child, x0, pos, y0, y1, node * 2, depth + 1);
    build(child + 1, pos, x1, y0, y1, node * 2 + 1, depth + 1);
  } else {
    build(child, x0, x1, y0, pos, node * 2, depth + 1);
    build(child + 1, x0, x1, pos, y1, node * 2 + 1, depth + 1);
  }
}

Rgb FaceTexture::colour(double s, double t) const {
  const int i = std::clamp(static_cast<int>(s * cell_inv_), 0, grid_w_ - 1);
  const int j = std::clamp(static_cast<int>(t * cell_inv_), 0, grid_h_ - 1);
  return walk(grid_[static_cast<size_t>(j) * grid_w_ + i], s, t);
}

Rgb FaceTexture::colourFromRoot(double s, double t) const { return walk(0, s, t); }

Rgb FaceTexture::walk(int start, double s, double t) const {
  const Style& st = style(material_);
  const Node* n = &nodes_[start];
  while (n->child >= 0) {
    const double c = n->split_x ? s : t;
    if (n->grout && std::abs(c - n->pos) < half_grout_) return {st.grout_val, st.grout_val, st.grout_val};
    n = &nodes_[n->child + (c >= n->pos ? 1 : 0)];
  }
  const Leaf& l = leaves_[n->leaf];
  if (l.plain) return l.c0;
  return leafColour(st, seed_hue_, l.hash, Palette{l.c0, l.c1}, s, t, l.x0, l.x1, l.y0, l.y1, true);
}

}  // namespace plslam::synth
