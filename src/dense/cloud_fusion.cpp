#include "dense/cloud_fusion.h"

#include <cmath>
#include <cstring>

#include "dense/voxel_grid.h"

namespace plslam {

Rgb classColour(int class_id) {
  if (class_id < 0) return {128, 128, 128};
  // Golden-ratio hues spread neighbouring ids far apart on the colour wheel.
  const double h = std::fmod(class_id * 0.6180339887498949, 1.0) * 6.0;
  const double s = 0.85, v = 0.95;
  const int i = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (i) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = q, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = q, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = q; break;
  }
  const auto u8 = [](double x) { return static_cast<uint8_t>(std::lround(x * 255.0)); };
  return {u8(r), u8(g), u8(b)};
}

Rgb semanticColour(int class_id, uint8_t r, uint8_t g, uint8_t b) {
  if (class_id >= 0) return classColour(class_id);
  const auto y = static_cast<uint8_t>(std::lround(0.299 * r + 0.587 * g + 0.114 * b));
  return {y, y, y};
}

Rgb semanticColour(const FusedPoint& p) { return semanticColour(p.class_id, p.r, p.g, p.b); }

std::vector<Eigen::Vector3f> worldPoints(const KeyFrame& kf, const SE3& T_out_w) {
  const SE3 T_out_c = T_out_w * kf.T_w_c;
  const Eigen::Matrix3f R = T_out_c.rotation().cast<float>();
  const Eigen::Vector3f t = T_out_c.translation().cast<float>();
  std::vector<Eigen::Vector3f> out;
  out.reserve(kf.dense.size());
  for (const DensePoint& p : kf.dense) out.push_back(R * p.p_c + t);
  return out;
}

std::vector<FusedPoint> fuseCloud(const Map& map, const DenseOptions& o, const DenseProgress& progress,
                                  bool* cancelled, const SE3& T_out_w) {
  if (cancelled) *cancelled = false;
  const size_t total = map.keyframes().size();
  size_t done = 0;
  std::vector<FusedPoint> out;
  if (o.fused_voxel_m <= 0) {
    for (const auto& [id, kf] : map.keyframes()) {
      const std::vector<Eigen::Vector3f> pw = worldPoints(kf, T_out_w);
      for (size_t i = 0; i < pw.size(); ++i) {
        const DensePoint& d = kf.dense[i];
        out.push_back({pw[i], d.r, d.g, d.b, d.class_id, 1});
      }
      if (progress && !progress("cloud", ++done, total)) {
        if (cancelled) *cancelled = true;
        break;
      }
    }
    return out;
  }
  dense_detail::VoxelAccumulator grid(o.fused_voxel_m);
  for (const auto& [id, kf] : map.keyframes()) {
    const std::vector<Eigen::Vector3f> pw = worldPoints(kf, T_out_w);
    for (size_t i = 0; i < pw.size(); ++i) {
      const DensePoint& d = kf.dense[i];
      grid.add(pw[i], d.r, d.g, d.b, d.class_id);
    }
    if (progress && !progress("cloud", ++done, total)) {
      if (cancelled) *cancelled = true;
      return out;
    }
  }
  out.reserve(grid.size());
  grid.forEach(std::max(1, o.min_voxel_points),
               [&](const Eigen::Vector3f& c, uint8_t r, uint8_t g, uint8_t b, int16_t cls, int n) {
                 out.push_back({c, r, g, b, cls, n});
               });
  return out;
}

std::string cloudToSemanticPly(const std::vector<FusedPoint>& cloud) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\n"
      "comment plslam dense cloud, world frame (metres); colour = semantic colour, class = class id (-1: none)\n"
      "element vertex " +
      std::to_string(cloud.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty int class\nend_header\n";
  const size_t header = s.size();
  constexpr size_t kRecord = 3 * 4 + 3 + 4;
  s.resize(header + cloud.size() * kRecord);
  char* out = s.data() + header;
  // x86 and ARM hosts are little-endian, as the format line says.
  for (const FusedPoint& p : cloud) {
    const Rgb c = semanticColour(p);
    const int32_t cls = p.class_id;
    std::memcpy(out, p.p_w.data(), 12);
    out[12] = static_cast<char>(c.r);
    out[13] = static_cast<char>(c.g);
    out[14] = static_cast<char>(c.b);
    std::memcpy(out + 15, &cls, 4);
    out += kRecord;
  }
  return s;
}

}  // namespace plslam
