#include "dense/floor_plane.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {

constexpr size_t kMaxSample = 30000;  // RANSAC on a strided subsample: the floor is large
constexpr int kIterations = 500;
constexpr int kMaxPlanes = 6;
constexpr double kSameSurfaceM = 0.15;  // level planes closer than this are one surface (see floorAmong)

struct Plane {
  Eigen::Vector3d n;  // unit, up side
  double d = 0;       // n . p = d on the plane
  int inliers = 0;
};

// Least-squares plane through `pts` (smallest-eigenvalue normal), oriented along `up`.
Plane fitPlane(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& up) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Plane pl;
  pl.n = es.eigenvectors().col(0).normalized();
  if (pl.n.dot(up) < 0) pl.n = -pl.n;
  pl.d = pl.n.dot(c);
  pl.inliers = static_cast<int>(pts.size());
  return pl;
}

// What the map frame is anchored to at the first keyframe: the robot base when its
// mounting is known (REP-105: the map starts at the robot, x its forward), else the camera.
struct Anchor {
  Eigen::Vector3d origin;    // world: the origin is put on the floor below it
  Eigen::Vector3d forward;   // world: laid onto the floor, the map's x
  Eigen::Vector3d fallback;  // world: x when `forward` is vertical (a camera looking straight down)
  Eigen::Vector3d up;        // world: the prior up of the floor search
};

Anchor anchorOf(const SE3& T_w_c0, const Eigen::Vector3d& up_c, const DenseOptions& o) {
  const Eigen::Matrix3d R = T_w_c0.rotation();
  const Eigen::Vector3d image_up = (R * up_c).normalized();
  if (!o.T_base_cam) return {T_w_c0.translation(), R.col(2), image_up, image_up};
  // The base's own z is a better prior up than the image's top: the mounting says how the
  // camera is tilted on the robot, and the base stands on the floor.
  const SE3 T_w_b0 = T_w_c0 * o.T_base_cam->inverse();
  const Eigen::Matrix3d Rb = T_w_b0.rotation();
  return {T_w_b0.translation(), Rb.col(0), image_up, Rb.col(2)};
}

SE3 gridFrame(const Eigen::Vector3d& up, double height0, const Anchor& a) {
  Eigen::Vector3d x = a.forward - a.forward.dot(up) * up;
  if (x.norm() < 1e-6) x = a.fallback - a.fallback.dot(up) * up;
  x.normalize();
  Eigen::Matrix3d Rg;
  Rg.col(0) = x;
  Rg.col(1) = up.cross(x);
  Rg.col(2) = up;
  const Eigen::Vector3d origin = a.origin - (up.dot(a.origin) - height0) * up;
  return SE3(Rg, origin);
}

FloorPlane gravityFloor(const std::vector<FusedPoint>& cloud, const Anchor& a, const std::string& method) {
  FloorPlane f;
  f.up_w = a.up.normalized();
  if (cloud.empty()) {
    f.height0 = f.up_w.dot(a.origin) - 1.0;
    f.method = method + " (empty cloud: floor 1 m below the anchor)";
  } else {
    std::vector<double> h;
    h.reserve(cloud.size());
    for (const FusedPoint& p : cloud) h.push_back(f.up_w.dot(p.p_w.cast<double>()));
    const size_t k = static_cast<size_t>(0.02 * (h.size() - 1));
    std::nth_element(h.begin(), h.begin() + k, h.end());
    f.height0 = h[k];
    f.method = method;
  }
  f.T_w_grid = gridFrame(f.up_w, f.height0, a);
  return f;
}

// With a camera-to-base transform: the floor is the base's own plane, through its origin at
// the first keyframe (the base's origin is on the floor, or a few centimetres above it).
FloorPlane baseFloor(const Anchor& a, const std::string& method) {
  FloorPlane f;
  f.up_w = a.up.normalized();
  f.height0 = f.up_w.dot(a.origin);
  f.method = method;
  f.T_w_grid = gridFrame(f.up_w, f.height0, a);
  return f;
}

std::vector<Plane> planesNotAboveTheBase(const std::vector<Plane>& level, const Anchor& a, double max_above_m) {
  std::vector<Plane> kept;
  for (const Plane& p : level)
    if (p.d - p.n.dot(a.origin) <= max_above_m) kept.push_back(p);  // the plane's height over the base's origin
  return kept;
}

// A strided subsample of the cloud: the floor is large.
std::vector<Eigen::Vector3d> subsample(const std::vector<FusedPoint>& cloud) {
  const size_t step = std::max<size_t>(1, cloud.size() / kMaxSample);
  std::vector<Eigen::Vector3d> pts;
  for (size_t i = 0; i < cloud.size(); i += step) pts.push_back(cloud[i].p_w.cast<double>());
  return pts;
}

// The lowest `fraction` of `pts` along the prior up: the floor is the lowest surface, and in
// a scene seen from the side (walls filling the view, the floor a thin band) it is under 5 %
// of all points but a large share of the low ones.
std::vector<Eigen::Vector3d> lowest(std::vector<Eigen::Vector3d> pts, const Eigen::Vector3d& up, double fraction) {
  const size_t keep = std::max<size_t>(3, static_cast<size_t>(fraction * pts.size()));
  if (keep >= pts.size()) return pts;
  std::nth_element(pts.begin(), pts.begin() + (keep - 1), pts.end(),
                   [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return up.dot(a) < up.dot(b); });
  pts.resize(keep);
  return pts;
}

// The plane refitted on every point of `pts` near it, twice: the low points it was found in
// hold only part of the floor when the prior up is tilted (the far floor looks lower than
// the near floor), and a partial floor tilts the fit towards the walls' bottom rows.
Plane refineOnAll(const Plane& plane, const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& up,
                  double thr) {
  Plane p = plane;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Eigen::Vector3d> in;
    for (const auto& q : pts)
      if (std::fabs(p.n.dot(q) - p.d) < thr) in.push_back(q);
    if (in.size() < 3) return p;
    p = fitPlane(in, up);
  }
  return p;
}

// Planes within the tilt limit of `up` holding at least floor_min_fraction of `pts`, each
// found by RANSAC on what the planes before it left (deterministic seed), refined by
// least squares on its inliers.
std::vector<Plane> levelPlanes(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& up,
                               const DenseOptions& o) {
  const int min_support = std::max(3, static_cast<int>(o.floor_min_fraction * pts.size()));
  const double cos_tilt = std::cos(o.floor_max_tilt_deg * M_PI / 180.0);
  const double thr = o.floor_inlier_m;
  std::mt19937 rng(12345);
  std::vector<Plane> level;
  std::vector<Eigen::Vector3d> remaining = pts;
  for (int round = 0; round < kMaxPlanes && remaining.size() >= static_cast<size_t>(min_support); ++round) {
    std::uniform_int_distribution<size_t> pick(0, remaining.size() - 1);
    Plane best;
    for (int it = 0; it < kIterations; ++it) {
      const Eigen::Vector3d& a = remaining[pick(rng)];
      const Eigen::Vector3d& b = remaining[pick(rng)];
      const Eigen::Vector3d& c = remaining[pick(rng)];
      Eigen::Vector3d n = (b - a).cross(c - a);
      if (n.norm() < 1e-9) continue;
      n.normalize();
      if (n.dot(up) < 0) n = -n;
      if (n.dot(up) < cos_tilt) continue;  // walls and slopes are no floor
      const double d = n.dot(a);
      int count = 0;
      for (const auto& p : remaining) count += std::fabs(n.dot(p) - d) < thr;
      if (count > best.inliers) best = {n, d, count};
    }
    if (best.inliers < min_support) break;
    std::vector<Eigen::Vector3d> in, out;
    for (const auto& p : remaining) (std::fabs(best.n.dot(p) - best.d) < thr ? in : out).push_back(p);
    Plane refined = fitPlane(in, up);
    if (refined.n.dot(up) >= cos_tilt) level.push_back(refined);
    remaining.swap(out);
  }
  return level;
}

// The floor among the level planes: the lowest along the prior up (a table top lies above
// the floor), but of planes within kSameSurfaceM of the lowest the one with the most points:
// they are layers of one surface (a floor seen doubled by drift, a rug), and a thin layer
// below the floor's bulk must not win.
const Plane* floorAmong(const std::vector<Plane>& level, const Eigen::Vector3d& up) {
  const auto height = [&](const Plane& p) { return p.d / p.n.dot(up); };
  const Plane* lowest_plane = &level.front();
  for (const Plane& p : level)
    if (height(p) < height(*lowest_plane)) lowest_plane = &p;
  const Plane* floor = lowest_plane;
  for (const Plane& p : level)
    if (height(p) < height(*lowest_plane) + kSameSurfaceM && p.inliers > floor->inliers) floor = &p;
  return floor;
}

}  // namespace

FloorPlane estimateFloor(const std::vector<FusedPoint>& cloud, const SE3& T_w_c0, const Eigen::Vector3d& up_c,
                         const DenseOptions& o) {
  if (!up_c.allFinite() || std::abs(up_c.norm() - 1.0) > 1e-9)
    throw DataError("estimateFloor: the camera's up must be a unit vector (PinholeCamera::imageUp())");
  const Anchor anchor = anchorOf(T_w_c0, up_c, o);
  if (o.floor == "gravity") return gravityFloor(cloud, anchor, "gravity");
  if (o.floor != "ransac") throw ConfigError("dense.floor: unknown method '" + o.floor + "' (ransac, gravity)");
  if (cloud.size() < 3) return gravityFloor(cloud, anchor, "gravity (no level plane found)");

  const Eigen::Vector3d up = anchor.up.normalized();
  const std::vector<Eigen::Vector3d> pts = subsample(cloud);
  std::vector<Plane> level = levelPlanes(lowest(pts, up, o.floor_search_fraction), up, o);
  if (level.empty()) return o.T_base_cam ? baseFloor(anchor, "base (no level plane found)")
                                         : gravityFloor(cloud, anchor, "gravity (no level plane found)");
  if (o.T_base_cam) {
    // The robot stands on the floor: a level plane above its base at the first keyframe is
    // a table, a shelf, or a band of points mistaken for a floor that had too few points to
    // be a candidate. (Below the base is allowed: its origin may be above the floor.)
    level = planesNotAboveTheBase(level, anchor, o.floor_max_above_base_m);
    if (level.empty()) return baseFloor(anchor, "base (no level plane at the base)");
  }
  const Plane* floor = floorAmong(level, up);
  const Plane refined = refineOnAll(*floor, pts, up, o.floor_inlier_m);
  FloorPlane f;
  f.up_w = refined.n;
  f.height0 = refined.d;
  f.method = "ransac";
  f.inliers = refined.inliers;
  f.candidates = static_cast<int>(level.size());
  f.T_w_grid = gridFrame(f.up_w, f.height0, anchor);
  return f;
}

MapFrame estimateMapFrame(const Map& map, const PinholeCamera& camera, const std::vector<FusedPoint>& cloud_w,
                          const DenseOptions& o, FloorPlane* floor_out) {
  std::vector<FusedPoint> sparse;
  if (cloud_w.empty())
    for (const auto& [id, p] : map.points()) sparse.push_back({p.p_w.cast<float>()});
  const SE3 T_w_c0 = map.keyframes().empty() ? SE3() : map.keyframes().begin()->second.T_w_c;
  const FloorPlane floor = estimateFloor(cloud_w.empty() ? sparse : cloud_w, T_w_c0, camera.imageUp(), o);
  if (floor_out) *floor_out = floor;
  MapFrame f;
  f.T_map_world = floor.T_w_grid.inverse();
  f.floor_method = floor.method;
  f.floor_source = cloud_w.empty() ? "sparse" : "dense";
  f.floor_points = floor.inliers;
  f.origin = o.T_base_cam ? "base" : "camera";
  return f;
}

}  // namespace plslam
