#include "dynamic/semantic_labels.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace plslam {

cv::Mat classImage(const Segmentation& s) {
  if (s.empty()) return {};
  CV_Assert(s.instance_ids.type() == CV_16UC1);
  std::vector<int16_t> lut(s.instances.size() + 1, -1);
  for (size_t k = 0; k < s.instances.size(); ++k) lut[k + 1] = static_cast<int16_t>(s.instances[k].class_id);
  cv::Mat out(s.instance_ids.size(), CV_16SC1);
  for (int v = 0; v < out.rows; ++v) {
    const uint16_t* id = s.instance_ids.ptr<uint16_t>(v);
    int16_t* o = out.ptr<int16_t>(v);
    for (int u = 0; u < out.cols; ++u) o[u] = id[u] < lut.size() ? lut[id[u]] : int16_t(-1);
  }
  return out;
}

std::vector<KeyframeInstance> describeInstances(const Segmentation& s, const std::vector<InstanceDecision>& decisions,
                                                const cv::Mat& depth_m, const PinholeCamera& camera) {
  std::vector<KeyframeInstance> out(s.instances.size());
  if (s.empty()) return out;
  const bool with_depth = !depth_m.empty() && depth_m.size() == s.instance_ids.size() && depth_m.type() == CV_32FC1;
  std::vector<std::vector<float>> xs(out.size()), ys(out.size()), zs(out.size());
  for (int v = 0; v < s.instance_ids.rows; ++v) {
    const uint16_t* id = s.instance_ids.ptr<uint16_t>(v);
    const float* d = with_depth ? depth_m.ptr<float>(v) : nullptr;
    for (int u = 0; u < s.instance_ids.cols; ++u) {
      if (id[u] == 0 || id[u] > out.size()) continue;
      const size_t k = id[u] - 1;
      ++out[k].pixels;
      // Every second pixel in each direction is plenty for a median.
      if (!d || (u | v) & 1 || !std::isfinite(d[u]) || d[u] <= 0) continue;
      const Eigen::Vector3d p = camera.unproject(Eigen::Vector2d(u, v), d[u]);
      xs[k].push_back(static_cast<float>(p.x()));
      ys[k].push_back(static_cast<float>(p.y()));
      zs[k].push_back(static_cast<float>(p.z()));
    }
  }
  auto median = [](std::vector<float>& a) {
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    return static_cast<double>(a[a.size() / 2]);
  };
  for (size_t k = 0; k < out.size(); ++k) {
    const Instance& in = s.instances[k];
    out[k].class_id = in.class_id;
    out[k].class_name = in.class_name;
    out[k].box = in.box;
    out[k].dynamic = k < decisions.size() && decisions[k].dynamic;
    if (!xs[k].empty()) out[k].centroid_c = {median(xs[k]), median(ys[k]), median(zs[k])};
  }
  return out;
}

}  // namespace plslam
