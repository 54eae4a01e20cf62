// Voxel downsampling by hashing (no PCL): one point per occupied voxel, the centroid of its
// points with their mean colour and most frequent class. Internal to the dense module.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace plslam::dense_detail {

/// Accumulates points voxel by voxel.
class VoxelAccumulator {
 public:
  explicit VoxelAccumulator(double voxel_m) : inv_(1.0 / voxel_m) {}

  void add(const Eigen::Vector3f& p, uint8_t r, uint8_t g, uint8_t b, int16_t class_id) {
    Cell& c = cells_[key(p)];
    if (c.count == 0) c.order = next_order_++;
    c.sum += p.cast<double>();
    c.rgb[0] += r;
    c.rgb[1] += g;
    c.rgb[2] += b;
    ++c.count;
    // Few classes meet in one voxel: a small list of (class, votes) does.
    for (auto& v : c.votes)
      if (v.first == class_id) {
        ++v.second;
        return;
      }
    c.votes.push_back({class_id, 1});
  }

  size_t size() const { return cells_.size(); }

  /// Calls f(centroid, r, g, b, class_id, count) once per voxel with at least `min_points`,
  /// in the order the voxels were first touched (deterministic for a given input order).
  template <typename F>
  void forEach(int min_points, F f) const {
    std::vector<const Cell*> ordered(cells_.size(), nullptr);
    for (const auto& kv : cells_) ordered[kv.second.order] = &kv.second;
    for (const Cell* c : ordered) {
      if (c->count < min_points) continue;
      const double n = c->count;
      int16_t best = -1;
      int best_votes = -1;
      for (const auto& v : c->votes)
        if (v.second > best_votes || (v.second == best_votes && v.first > best)) {
          best = v.first;
          best_votes = v.second;
        }
      f(Eigen::Vector3f((c->sum / n).cast<float>()), static_cast<uint8_t>(std::lround(c->rgb[0] / n)),
        static_cast<uint8_t>(std::lround(c->rgb[1] / n)), static_cast<uint8_t>(std::lround(c->rgb[2] / n)), best,
        c->count);
    }
  }

 private:
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double rgb[3] = {0, 0, 0};
    int count = 0;
    size_t order = 0;
    std::vector<std::pair<int16_t, int>> votes;
  };
  uint64_t key(const Eigen::Vector3f& p) const {
    // 21 bits per axis: +-1e6 voxels, far beyond any room or building at cm resolution.
    const auto q = [&](float v) {
      return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v * inv_)) + (1 << 20)) & 0x1FFFFF;
    };
    return q(p.x()) | (q(p.y()) << 21) | (q(p.z()) << 42);
  }
  double inv_;
  size_t next_order_ = 0;
  std::unordered_map<uint64_t, Cell> cells_;
};

}  // namespace plslam::dense_detail
