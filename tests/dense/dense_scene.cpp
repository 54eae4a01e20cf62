#include "dense_scene.h"

#include <octomap/OcTree.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
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
  GtMap g{synth::makeScene(o.kind, so), Map(), {}, SE3()};
  if (o.first_camera_world) g.T_scene_world = g.scene.cameraPose(0);
  const SE3 T_world_scene = g.T_scene_world.inverse();
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
    kf.T_w_c = T_world_scene * f.T_w_c;
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

SE3 trueMapFrame(const SE3& T_scene_c0) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ(), f = T_scene_c0.rotation().col(2);
  const Eigen::Vector3d x = (f - f.dot(up) * up).normalized();
  Eigen::Matrix3d R;
  R << x, up.cross(x), up;
  const Eigen::Vector3d c = T_scene_c0.translation();
  return SE3(R, Eigen::Vector3d(c.x(), c.y(), 0));
}

namespace {

// Angle (degrees) between a plane's normal fitted to `pts` and the horizontal.
double tiltOfPlaneDeg(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  return std::asin(std::min(1.0, std::abs(n.z()))) * 180 / M_PI;
}

// Clear of the furniture (every static box but the room) by `margin`.
bool clearOfFurniture(const synth::Scene& scene, const Eigen::Vector3d& p, double margin) {
  for (size_t i = 1; i < scene.staticBoxes().size(); ++i)
    if (scene.staticBoxes()[i].signedDistance(p) < margin) return false;
  return true;
}

// The vertical faces of the static boxes (the room's walls and the furniture's sides): for
// each, the voxels (map frame) whose scene point `p` lies on it, away from its edges.
std::vector<std::vector<Eigen::Vector3d>> verticalFaces(const synth::Scene& scene,
                                                        const std::vector<Eigen::Vector3d>& voxels,
                                                        const SE3& T_scene_map, double res) {
  const std::vector<synth::Box>& boxes = scene.staticBoxes();
  std::vector<std::vector<Eigen::Vector3d>> faces(4 * boxes.size());  // box b: -x, +x, -y, +y
  for (const Eigen::Vector3d& v : voxels) {
    const Eigen::Vector3d p = T_scene_map * v;
    for (size_t b = 0; b < boxes.size(); ++b) {
      const Eigen::Vector3d q = boxes[b].T_w_b.inverse() * p, h = boxes[b].half_size;
      const double margin = boxes[b].inward ? 0.3 : 0.1;
      for (int a = 0; a < 2; ++a) {
        const int o = 1 - a;  // the face's other horizontal axis
        if (std::abs(std::abs(q[a]) - h[a]) < res && std::abs(q[o]) < h[o] - margin && std::abs(q.z()) < h.z() - margin)
          faces[4 * b + 2 * a + (q[a] > 0)].push_back(v);
      }
    }
  }
  return faces;
}

}  // namespace

MapFrameCheck checkMapFrame(const synth::Scene& scene, const SE3& T_scene_world, const SE3& T_map_world,
                            const octomap::OcTree& tree) {
  MapFrameCheck k;
  const SE3 T_map_world_true = trueMapFrame(T_scene_world).inverse() * T_scene_world;
  k.rotation_error_deg = (T_map_world.inverse() * T_map_world_true).angle() * 180 / M_PI;
  const Eigen::Vector3d up_est = T_map_world.rotation().row(2), up_true = T_map_world_true.rotation().row(2);
  k.up_error_deg = std::acos(std::min(1.0, up_est.dot(up_true))) * 180 / M_PI;
  k.camera_height_m = T_map_world.translation().z();
  k.true_camera_height_m = T_map_world_true.translation().z();

  const double res = tree.getResolution();
  const synth::Box& room = scene.room();
  const Eigen::Vector3d half = room.half_size, centre = room.T_w_b.translation();
  const SE3 T_scene_map = T_scene_world * T_map_world.inverse();
  const std::vector<Eigen::Vector3d> voxels = occupiedVoxelCentres(tree);
  std::vector<double> floor_z;
  for (const Eigen::Vector3d& v : voxels) {
    const Eigen::Vector3d p = T_scene_map * v - centre;  // scene, about the room's centre (axis-aligned)
    const bool clear = clearOfFurniture(scene, p + centre, 2 * res);
    const double to_x = half.x() - std::abs(p.x()), to_y = half.y() - std::abs(p.y());
    if (clear && std::abs(p.z() + half.z()) < 1.5 * res && to_x > 2 * res && to_y > 2 * res) floor_z.push_back(v.z());
  }
  k.floor_voxels = static_cast<int>(floor_z.size());
  if (!floor_z.empty()) {
    for (double z : floor_z) k.floor_mean_z += z / floor_z.size();
    std::vector<double> a;
    for (double z : floor_z) a.push_back(std::abs(z));
    std::sort(a.begin(), a.end());
    k.floor_p95_abs_z = a[static_cast<size_t>(0.95 * (a.size() - 1))];
  }
  const std::vector<std::vector<Eigen::Vector3d>> faces = verticalFaces(scene, voxels, T_scene_map, res);
  for (size_t i = 0; i < faces.size(); ++i)
    if (faces[i].size() >= 100) {
      static const char* kSide[] = {" -x", " +x", " -y", " +y"};
      k.faces.push_back({scene.staticBoxes()[i / 4].name + kSide[i % 4], static_cast<int>(faces[i].size()),
                         tiltOfPlaneDeg(faces[i])});
      k.max_wall_tilt_deg = std::max(k.max_wall_tilt_deg, k.faces.back().tilt_deg);
    }
  return k;
}

std::string MapFrameCheck::facesText() const {
  std::string s;
  char b[160];
  for (const Face& f : faces) {
    std::snprintf(b, sizeof b, "%s%s: %d voxels, tilt %.2f deg", s.empty() ? "" : "; ", f.name.c_str(), f.voxels,
                  f.tilt_deg);
    s += b;
  }
  return s;
}

}  // namespace plslam::test
