#include "dense_scene.h"

#include <octomap/OcTree.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "dense/keyframe_cloud.h"
#include "synth/renderer.h"

namespace plslam::test {

GtMap buildGtMap(const GtMapOptions& o) {
  synth::SceneOptions so;
  so.frames = o.frames;
  so.width = o.width;
  so.height = o.height;
  so.aa_samples = 1;
  so.noise.enabled = o.noise;
  GtMap g{synth::makeScene(o.kind, so), Map(), {}};
  const PinholeCamera& camera = g.scene.camera();
  for (int i = 0; i < o.frames; i += o.every) {
    const synth::RenderedFrame f = synth::render(g.scene, i);
    cv::Mat mask, classes;
    if (!g.scene.movingObjects().empty()) {
      // The exact masks: every moving object is a person (class 0).
      const cv::Mat moving = f.instance_ids != 0;
      if (o.reject) mask = ~moving;
      classes = cv::Mat(f.instance_ids.size(), CV_16SC1, cv::Scalar(-1));
      classes.setTo(0, moving);
    }
    KeyFrame kf;
    kf.t_ns = f.t_ns;
    kf.T_w_c = f.T_w_c;
    kf.dense = makeKeyframeCloud(camera, f.bgr, f.depth_m, mask, classes, o.dense);
    g.map.addKeyFrame(std::move(kf));
    g.keyframe_times.push_back(f.t_ns);
  }
  return g;
}

int pointsOnMovingPath(const synth::Scene& scene, const std::vector<Eigen::Vector3d>& points,
                       const std::vector<TimeNs>& times, double tolerance, double static_margin) {
  std::vector<synth::Box> boxes;  // the persons' parts at every time
  for (TimeNs t : times)
    for (const synth::Box& b : scene.movingBoxes(t)) boxes.push_back(b);
  int n = 0;
  for (const Eigen::Vector3d& p : points) {
    if (scene.staticSurfaceDistance(p) <= static_margin) continue;
    for (const synth::Box& b : boxes)
      if (b.signedDistance(p) <= tolerance) {
        ++n;
        break;
      }
  }
  return n;
}

double fractionOnStaticSurfaces(const synth::Scene& scene, const std::vector<FusedPoint>& points, double distance) {
  if (points.empty()) return 0;
  size_t on = 0;
  for (const FusedPoint& p : points) on += scene.staticSurfaceDistance(p.p_w.cast<double>()) <= distance;
  return static_cast<double>(on) / points.size();
}

std::vector<Eigen::Vector3d> occupiedVoxelCentres(const octomap::OcTree& tree) {
  std::vector<Eigen::Vector3d> out;
  const double res = tree.getResolution();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const double size = it.getSize();
    const int n = std::max(1, static_cast<int>(std::lround(size / res)));
    const octomap::point3d c = it.getCoordinate();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k)
          out.emplace_back(c.x() - size / 2 + (i + 0.5) * res, c.y() - size / 2 + (j + 0.5) * res,
                           c.z() - size / 2 + (k + 0.5) * res);
  }
  return out;
}

}  // namespace plslam::test
