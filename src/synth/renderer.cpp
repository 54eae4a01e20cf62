#include "synth/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "core/error.h"
#include "core/log.h"
#include "synth/box_ray.h"
#include "synth/hash.h"

namespace plslam::synth {

namespace {

constexpr double kNear = 1e-3;  // rays start 1 mm in front of the camera
constexpr int kTile = 16;

/// A box as seen from the current camera: ray directions d_c = (xn, yn, 1) map to the box
/// frame by R (row-major), the camera centre is o in the box frame.
struct Prepared {
  double R[9];
  double o[3];
  double h[3];
  bool inward = false;
  int instance = 0;
  const Box* box = nullptr;
  float shade[6];
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // conservative pixel rectangle (inclusive)
  std::array<const FaceTexture*, 6> static_textures{};            // the scene's, for static boxes
  mutable std::array<std::unique_ptr<FaceTexture>, 6> textures;  // moving boxes: built on first use (one thread)
};

struct Hit {
  double s = std::numeric_limits<double>::infinity();  // = depth z, since d_c has z = 1
  int box = -1;
  int face = -1;
  double d[3] = {0, 0, 0};  // the ray direction in the hit box's frame
};

inline void boxDir(const Prepared& p, double xn, double yn, double d[3]) {
  d[0] = p.R[0] * xn + p.R[1] * yn + p.R[2];
  d[1] = p.R[3] * xn + p.R[4] * yn + p.R[5];
  d[2] = p.R[6] * xn + p.R[7] * yn + p.R[8];
}

class FrameRenderer {
 public:
  FrameRenderer(const Scene& scene, const SE3& T_w_c, TimeNs t_ns)
      : cam_(scene.camera()), boxes_(scene.boxesAt(t_ns)) {
    const Eigen::Vector3d light = Eigen::Vector3d(0.4, 0.25, 0.88).normalized();
    prepared_.resize(boxes_.size());
    for (size_t i = 0; i < boxes_.size(); ++i) {
      const Box& b = boxes_[i];
      Prepared& p = prepared_[i];
      const SE3 T_b_c = b.T_w_b.inverse() * T_w_c;
      const Eigen::Matrix3d R = T_b_c.rotation();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) p.R[r * 3 + c] = R(r, c);
      for (int k = 0; k < 3; ++k) {
        p.o[k] = T_b_c.translation()[k];
        p.h[k] = b.half_size[k];
      }
      p.inward = b.inward;
      p.instance = b.instance_id;
      p.box = &b;
      if (i < scene.staticBoxes().size())
        for (int f = 0; f < 6; ++f) p.static_textures[f] = &scene.staticTexture(i, f);
      for (int f = 0; f < 6; ++f) {
        Eigen::Vector3d n = Eigen::Vector3d::Zero();
        n[f / 2] = (f & 1) ? 1.0 : -1.0;
        if (b.inward) n = -n;
        const double l = (b.T_w_b.quaternion() * n).dot(light);
        p.shade[f] = static_cast<float>(0.55 + 0.45 * (0.5 + 0.5 * l));
      }
      if (!b.inward) screenRect(b, T_b_c.inverse(), &p);
    }
    buildTiles();
  }

  /// Nearest hit of the ray through normalised image point (xn, yn) in pixel tile `tile`.
  Hit trace(double xn, double yn, int tile) const {
    Hit hit;
    double d[3];
    int face = -1;
    double s = 0;
    for (int k = tile_start_[tile]; k < tile_start_[tile + 1]; ++k) {
      const Prepared& p = prepared_[tile_boxes_[k]];
      boxDir(p, xn, yn, d);
      if (intersectBox(p.o, d, p.h, false, kNear, &s, &face, hit.s)) {
        hit.s = s;
        hit.box = tile_boxes_[k];
        hit.face = face;
        std::copy(d, d + 3, hit.d);
      }
    }
    // The room (box 0) encloses everything: only needed when nothing else was hit.
    if (hit.box < 0) {
      const Prepared& p = prepared_[0];
      boxDir(p, xn, yn, d);
      if (intersectBox(p.o, d, p.h, true, kNear, &s, &face)) {
        hit.s = s;
        hit.box = 0;
        hit.face = face;
        std::copy(d, d + 3, hit.d);
      }
    }
    return hit;
  }

  Rgb shade(const Hit& hit) const {
    if (hit.box < 0) return {};
    const Prepared& p = prepared_[hit.box];
    const double* d = hit.d;
    const int a = hit.face / 2, b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
    const double qb = p.o[b] + hit.s * d[b], qc = p.o[c] + hit.s * d[c];
    const Box& box = *p.box;
    const FaceTexture* tex = p.static_textures[hit.face];
    if (!tex) {  // a moving box: built on first use (most faces are never seen)
      auto& own = p.textures[hit.face];
      if (!own) own = std::make_unique<FaceTexture>(makeFaceTexture(box, hit.face));
      tex = own.get();
    }
    const Rgb col = tex->colour(qb + p.h[b], qc + p.h[c]);
    const float k = p.shade[hit.face];
    return {col.r * k, col.g * k, col.b * k};
  }

  /// |cos| of the angle between the ray and the surface normal.
  static double incidenceCos(const Hit& hit) {
    const double* d = hit.d;
    return std::abs(d[hit.face / 2]) / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  }

  int instanceOf(const Hit& hit) const { return hit.box < 0 ? 0 : prepared_[hit.box].instance; }
  int tileOf(int x, int y) const { return (y / kTile) * tiles_x_ + x / kTile; }

 private:
  void screenRect(const Box& b, const SE3& T_c_b, Prepared* p) const {
    std::array<Eigen::Vector3d, 8> c;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d q((i & 1) ? b.half_size.x() : -b.half_size.x(), (i & 2) ? b.half_size.y() : -b.half_size.y(),
                              (i & 4) ? b.half_size.z() : -b.half_size.z());
      c[i] = T_c_b * q;
    }
    double u0 = std::numeric_limits<double>::infinity(), v0 = u0, u1 = -u0, v1 = -u0;
    bool any = false;
    auto addPoint = [&](const Eigen::Vector3d& q) {
      const double u = cam_.fx * q.x() / q.z() + cam_.cx, v = cam_.fy * q.y() / q.z() + cam_.cy;
      u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
      any = true;
    };
    // The part of the box in front of the near plane: its front corners and the points
    // where its edges cross the plane.
    const double zc = kNear * 0.5;
    for (int i = 0; i < 8; ++i) {
      if (c[i].z() >= zc) addPoint(c[i]);
      for (int bit = 1; bit < 8; bit <<= 1) {
        if (i & bit) continue;
        const Eigen::Vector3d &e0 = c[i], &e1 = c[i | bit];
        if ((e0.z() < zc) != (e1.z() < zc)) {
          const double a = (zc - e0.z()) / (e1.z() - e0.z());
          addPoint(e0 + a * (e1 - e0));
        }
      }
    }
    if (!any) return;
    const double big = 1e7;
    p->x0 = static_cast<int>(std::max(0.0, std::floor(std::max(-big, u0)) - 1));
    p->y0 = static_cast<int>(std::max(0.0, std::floor(std::max(-big, v0)) - 1));
    p->x1 = static_cast<int>(std::min(cam_.width - 1.0, std::ceil(std::min(big, u1)) + 1));
    p->y1 = static_cast<int>(std::min(cam_.height - 1.0, std::ceil(std::min(big, v1)) + 1));
  }

  void buildTiles() {
    tiles_x_ = (cam_.width + kTile - 1) / kTile;
    const int tiles_y = (cam_.height + kTile - 1) / kTile;
    std::vector<int> count(tiles_x_ * tiles_y + 1, 0);
    auto forTiles = [&](const Prepared& p, auto&& fn) {
      if (p.x1 < p.x0 || p.y1 < p.y0) return;
      for (int ty = p.y0 / kTile; ty <= p.y1 / kTile; ++ty)
        for (int tx = p.x0 / kTile; tx <= p.x1 / kTile; ++tx) fn(ty * tiles_x_ + tx);
    };
    for (size_t i = 1; i < prepared_.size(); ++i) forTiles(prepared_[i], [&](int t) { ++count[t + 1]; });
    tile_start_.assign(count.size(), 0);
    std::partial_sum(count.begin(), count.end(), tile_start_.begin());
    tile_boxes_.resize(tile_start_.back());
    std::vector<int> fill(tile_start_.begin(), tile_start_.end() - 1);
    for (size_t i = 1; i < prepared_.size(); ++i)
      forTiles(prepared_[i], [&](int t) { tile_boxes_[fill[t]++] = static_cast<int>(i); });
  }

  const PinholeCamera& cam_;
  std::vector<Box> boxes_;
  std::vector<Prepared> prepared_;
  int tiles_x_ = 0;
  std::vector<int> tile_start_, tile_boxes_;
};

/// Sub-pixel offsets in (-0.5, 0.5): a rook pattern (n distinct columns and rows), odd
/// columns first so that the first half of the samples already spans the whole pixel.
std::vector<std::pair<double, double>> samplePattern(int n) {
  int k = std::max(1, static_cast<int>(std::lround(n * 0.618)));
  while (std::gcd(k, n) != 1) ++k;
  std::vector<std::pair<double, double>> out;
  for (int start : {1, 0})
    for (int i = start; i < n; i += 2) out.push_back({(i + 0.5) / n - 0.5, ((i * k) % n + 0.5) / n - 0.5});
  return out;
}

/// A standard normal value from one hash: the sum of twelve 5-bit uniforms (the classic
/// sum-of-12 approximation; tails end at 6 sigma), much cheaper than Box-Muller.
inline double gaussian12(uint64_t h) {
  int sum = 0;
  for (int k = 0; k < 12; ++k) sum += static_cast<int>((h >> (5 * k)) & 31);
  return (sum - 186.0) * (1.0 / 31.984371);  // mean 12 * 15.5, sd sqrt(12 * 1023 / 12)
}

/// Three roughly normal values (unit variance) from one hash: each the sum of four 5-bit uniforms.
inline void threeGaussians(uint64_t h, float out[3]) {
  for (int c = 0; c < 3; ++c) {
    int sum = 0;
    for (int k = 0; k < 4; ++k) sum += static_cast<int>((h >> (20 * c + 5 * k)) & 31);
    out[c] = (static_cast<float>(sum) - 62.0f) * (1.0f / 18.466185f);  // mean 62, sd sqrt(4 * 1023 / 12)
  }
}

/// What the rays through the pixel centres saw, and the colour of every pixel.
struct Shot {
  std::vector<double> z;     // depth, NaN where nothing was hit
  std::vector<int> key;      // box * 6 + face
  std::vector<Rgb> col;      // linear colour in [0, 1], anti-aliased at edges
  std::vector<float> cosi;   // |cos| of the incidence angle (only with noise)
  cv::Mat ids;               // CV_16UC1 instance ids
};

void traceCentres(const FrameRenderer& fr, const PinholeCamera& cam, bool noise, Shot* s) {
  const int W = cam.width, H = cam.height;
  const size_t npix = static_cast<size_t>(W) * H;
  s->z.resize(npix);
  s->key.resize(npix);
  s->col.resize(npix);
  s->cosi.resize(npix);
  s->ids.create(H, W, CV_16UC1);
  for (int y = 0; y < H; ++y) {
    const double yn = (y - cam.cy) / cam.fy;
    auto* ids = s->ids.ptr<uint16_t>(y);
    for (int x = 0; x < W; ++x) {
      const double xn = (x - cam.cx) / cam.fx;
      const Hit hit = fr.trace(xn, yn, fr.tileOf(x, y));
      const int i = y * W + x;
      s->z[i] = hit.box < 0 ? std::numeric_limits<double>::quiet_NaN() : hit.s;
      s->key[i] = hit.box * 6 + hit.face;
      s->col[i] = fr.shade(hit);
      s->cosi[i] = hit.box < 0 || !noise ? 0.f : static_cast<float>(FrameRenderer::incidenceCos(hit));
      ids[x] = static_cast<uint16_t>(fr.instanceOf(hit));
    }
  }
}

/// Marks the pixels whose centre differs from a neighbour's (another face, or a texture edge).
void findEdges(const Shot& s, int W, int H, std::vector<uint8_t>* edge) {
  edge->assign(static_cast<size_t>(W) * H, 0);
  auto differs = [&](int i, int j) {
    if (s.key[i] != s.key[j]) return true;
    const Rgb &a = s.col[i], &b = s.col[j];
    return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) > 0.04f;
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int i = y * W + x;
      if (x + 1 < W && differs(i, i + 1)) (*edge)[i] = (*edge)[i + 1] = 1;
      if (y + 1 < H && differs(i, i + W)) (*edge)[i] = (*edge)[i + W] = 1;
    }
}

/// Edge pixels get the average of `samples` sub-pixel samples.
void antiAlias(const FrameRenderer& fr, const PinholeCamera& cam, int samples, Shot* s) {
  thread_local std::vector<uint8_t> edge;
  const int W = cam.width, H = cam.height;
  findEdges(*s, W, H, &edge);
  // Half the samples first; a pixel they find uniform (it only neighbours an edge) stops there.
  const auto pattern = samplePattern(samples);
  const size_t first = (pattern.size() + 1) / 2;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int i = y * W + x;
      if (!edge[i]) continue;
      Rgb acc, lo{9, 9, 9}, hi{-9, -9, -9};
      int key0 = -2;
      bool uniform = true;
      size_t used = 0;
      for (size_t k = 0; k < pattern.size(); ++k) {
        if (k == first && uniform && hi.r - lo.r + hi.g - lo.g + hi.b - lo.b < 0.01f) break;
        const double xn = (x + pattern[k].first - cam.cx) / cam.fx, yn = (y + pattern[k].second - cam.cy) / cam.fy;
        const Hit hit = fr.trace(xn, yn, fr.tileOf(x, y));
        const Rgb c = fr.shade(hit);
        const int kk = hit.box * 6 + hit.face;
        if (key0 == -2) key0 = kk;
        uniform &= kk == key0;
        lo = {std::min(lo.r, c.r), std::min(lo.g, c.g), std::min(lo.b, c.b)};
        hi = {std::max(hi.r, c.r), std::max(hi.g, c.g), std::max(hi.b, c.b)};
        acc.r += c.r, acc.g += c.g, acc.b += c.b;
        ++used;
      }
      const float k = 1.0f / static_cast<float>(used);
      s->col[i] = {acc.r * k, acc.g * k, acc.b * k};
    }
}

/// Traces the view from T_w_c at time t into `s`, anti-aliased.
void shoot(const Scene& scene, const SE3& T_w_c, TimeNs t_ns, Shot* s) {
  const FrameRenderer fr(scene, T_w_c, t_ns);
  traceCentres(fr, scene.camera(), scene.options().noise.enabled, s);
  if (scene.options().aa_samples > 1) antiAlias(fr, scene.camera(), scene.options().aa_samples, s);
}

/// Sub-frames over the exposure of the frame at t, so that consecutive ones are at most
/// blur_step_px apart in the image: the largest displacement over the exposure of a 5 x 5
/// grid of pixels (corners included) at the depth the frame sees there.
int subframeCount(const Scene& scene, TimeNs t_ns, const std::vector<double>& z) {
  const TimeNs e = scene.exposureNs();
  if (e <= 0) return 1;
  const PinholeCamera& cam = scene.camera();
  const SE3 T_w_c = scene.cameraPoseAt(t_ns);
  const SE3 T_0_c = scene.cameraPoseAt(t_ns - e / 2).inverse() * T_w_c;
  const SE3 T_1_c = scene.cameraPoseAt(t_ns + e / 2).inverse() * T_w_c;
  double widest = 0;
  for (int gy = 0; gy < 5; ++gy)
    for (int gx = 0; gx < 5; ++gx) {
      const int x = gx * (cam.width - 1) / 4, y = gy * (cam.height - 1) / 4;
      const double d = z[static_cast<size_t>(y) * cam.width + x];
      const double depth = std::isfinite(d) ? d : 100.0;  // nothing hit: rotation only
      const Eigen::Vector3d p((x - cam.cx) / cam.fx * depth, (y - cam.cy) / cam.fy * depth, depth);
      const Eigen::Vector3d a = T_0_c * p, b = T_1_c * p;
      if (a.z() < 0.05 || b.z() < 0.05) continue;
      const Eigen::Vector2d ua(cam.fx * a.x() / a.z(), cam.fy * a.y() / a.z()), ub(cam.fx * b.x() / b.z(), cam.fy * b.y() / b.z());
      widest = std::max(widest, (ub - ua).norm());
    }
  const auto& f = scene.options().fast;
  return std::clamp(static_cast<int>(std::ceil(widest / f.blur_step_px)), 1, f.max_subframes);
}

/// Replaces s->col by the average colour over the frame's exposure: n sub-frames at the
/// midpoints of n equal parts of [t - e/2, t + e/2] (physically correct blur from the true path).
void blurOverExposure(const Scene& scene, TimeNs t_ns, int n, Shot* s) {
  thread_local Shot sub;
  thread_local std::vector<Rgb> acc;
  acc.assign(s->col.size(), Rgb{});
  const double e = static_cast<double>(scene.exposureNs());
  for (int k = 0; k < n; ++k) {
    const TimeNs tk = t_ns + static_cast<TimeNs>(std::llround(e * ((k + 0.5) / n - 0.5)));
    shoot(scene, scene.cameraPoseAt(tk), tk, &sub);
    for (size_t i = 0; i < acc.size(); ++i) acc[i].r += sub.col[i].r, acc[i].g += sub.col[i].g, acc[i].b += sub.col[i].b;
  }
  const float k = 1.0f / static_cast<float>(n);
  for (size_t i = 0; i < acc.size(); ++i) s->col[i] = {acc[i].r * k, acc[i].g * k, acc[i].b * k};
}

/// Noise of pixel i, sub-stream k of a frame's noise stream (counter-based: one mix per value).
struct PixelNoise {
  uint64_t stream;
  uint64_t operator()(int i, uint64_t k) const {
    return mix64(stream + (static_cast<uint64_t>(i) * 4 + k) * 0x9E3779B97F4A7C15ULL);
  }
};

/// 8-bit BGR from linear colour: times the exposure gain, plus sensor noise after it.
cv::Mat colourImage(const std::vector<Rgb>& col, int W, int H, float gain, float sigma, const PixelNoise& noise) {
  cv::Mat bgr(H, W, CV_8UC3);
  const float k = 255.f * gain;
  for (int y = 0; y < H; ++y) {
    auto* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < W; ++x) {
      const int i = y * W + x;
      float c[3] = {col[i].b * k, col[i].g * k, col[i].r * k};
      if (sigma > 0) {
        float g[3];
        threeGaussians(noise(i, 0), g);
        for (int j = 0; j < 3; ++j) c[j] += sigma * g[j];
      }
      for (int j = 0; j < 3; ++j) row[x][j] = cv::saturate_cast<uint8_t>(c[j]);
    }
  }
  return bgr;
}

/// Metric depth with the Kinect-like imperfections of DepthNoiseOptions.
cv::Mat depthImage(const Shot& s, int W, int H, const DepthNoiseOptions& nz, const PixelNoise& noise) {
  cv::Mat depth(H, W, CV_32FC1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<double>& z = s.z;
  for (int y = 0; y < H; ++y) {
    float* row = depth.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      const int i = y * W + x;
      double d = z[i];
      if (!nz.enabled || !std::isfinite(d)) {
        row[x] = std::isfinite(d) ? static_cast<float>(d) : nan;
        continue;
      }
      bool drop = d < nz.min_depth_m || d > nz.max_depth_m || s.cosi[i] < nz.grazing_cos ||
                  unitFromHash(noise(i, 1)) < nz.dropout_fraction;
      // The far side of a depth jump reads nothing (as the Kinect's occlusion shadow).
      const double jump = nz.edge_jump_m + 0.02 * d;
      if (!drop && ((x > 0 && z[i - 1] < d - jump) || (x + 1 < W && z[i + 1] < d - jump) ||
                    (y > 0 && z[i - W] < d - jump) || (y + 1 < H && z[i + W] < d - jump)))
        drop = true;
      if (drop) {
        row[x] = nan;
        continue;
      }
      d += nz.sigma_k * d * d * gaussian12(noise(i, 2));
      if (nz.quantum_m > 0) d = std::round(d / nz.quantum_m) * nz.quantum_m;
      row[x] = d > 0 ? static_cast<float>(d) : nan;
    }
  }
  return depth;
}

/// The frame from a shot: colour with gain and noise, depth with noise, instance ids.
RenderedFrame develop(const Scene& scene, const Shot& s, const SE3& T_w_c, TimeNs t_ns, uint64_t noise_stream) {
  const SceneOptions& opt = scene.options();
  const int W = scene.camera().width, H = scene.camera().height;
  const PixelNoise noise{hash3(opt.seed, 0xd371, noise_stream)};
  const float sigma = opt.noise.enabled ? static_cast<float>(opt.noise.colour_sigma) : 0.f;
  RenderedFrame out;
  out.t_ns = t_ns;
  out.T_w_c = T_w_c;
  out.gain = scene.exposureGain(t_ns);
  out.bgr = colourImage(s.col, W, H, static_cast<float>(out.gain), sigma, noise);
  out.depth_m = depthImage(s, W, H, opt.noise, noise);
  out.instance_ids = s.ids.clone();  // the shot is scratch reused by the next frame
  return out;
}

/// Per-thread scratch of the frame being rendered, reused from frame to frame.
Shot& frameShot() {
  thread_local Shot shot;
  return shot;
}

}  // namespace

RgbdFrame RenderedFrame::toRgbdFrame() const {
  RgbdFrame f;
  f.t_ns = t_ns;
  f.index = index;
  f.bgr = bgr;
  f.depth_m = depth_m;
  f.instance_ids = instance_ids;
  f.name = "synthetic/" + std::to_string(index);
  return f;
}

RenderedFrame render(const Scene& scene, int frame_index) {
  if (frame_index < 0 || frame_index >= scene.frameCount())
    throw ConfigError(str("synthetic render: frame ", frame_index, " outside [0, ", scene.frameCount(), ")"));
  const TimeNs t_ns = scene.frameTime(frame_index);
  const SE3 T_w_c = scene.cameraPose(frame_index);
  Shot& shot = frameShot();
  shoot(scene, T_w_c, t_ns, &shot);
  // Depth, ids and pose stay those at the stamp; only the colour integrates over the exposure.
  const int n = subframeCount(scene, t_ns, shot.z);
  if (n > 1) blurOverExposure(scene, t_ns, n, &shot);
  RenderedFrame f = develop(scene, shot, T_w_c, t_ns, static_cast<uint64_t>(frame_index));
  f.index = frame_index;
  f.subframes = n;
  return f;
}

RenderedFrame renderView(const Scene& scene, const SE3& T_w_c, TimeNs t_ns, uint64_t noise_stream) {
  Shot& shot = frameShot();
  shoot(scene, T_w_c, t_ns, &shot);
  return develop(scene, shot, T_w_c, t_ns, noise_stream);
}

}  // namespace plslam::synth
