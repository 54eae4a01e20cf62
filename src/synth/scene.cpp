#include "synth/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/log.h"
#include "synth/box_ray.h"
#include "synth/hash.h"

namespace plslam::synth {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kTwoPi = 2.0 * M_PI;

Eigen::Quaterniond yawQ(double yaw_rad) { return Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ())); }

double wave(double t, double period, double phase) { return std::sin(kTwoPi * t / period + phase); }

/// Ramanujan's approximation of an ellipse's perimeter.
double ellipsePerimeter(double a, double b) { return M_PI * (3 * (a + b) - std::sqrt((3 * a + b) * (a + 3 * b))); }

class Builder {
 public:
  explicit Builder(uint64_t seed) : seed_(seed) {}
  Box& add(const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& half, double yaw_deg,
           Material m) {
    Box b;
    b.name = name;
    b.T_w_b = SE3(yawQ(yaw_deg * kDeg), centre);
    b.half_size = half;
    b.materials.fill(m);
    b.texture_seed = hash2(seed_, boxes.size() + 1);
    boxes.push_back(b);
    return boxes.back();
  }
  /// A box placed relative to a parent pose given in the world (centre and yaw local to it).
  Box& addRelative(const std::string& name, const SE3& T_w_parent, const Eigen::Vector3d& centre_local,
                   const Eigen::Vector3d& half, double yaw_deg, Material m) {
    const SE3 T_w_b = T_w_parent * SE3(yawQ(yaw_deg * kDeg), centre_local);
    Box& b = add(name, T_w_b.translation(), half, 0, m);
    b.T_w_b = T_w_b;
    return b;
  }
  std::vector<Box> boxes;

 private:
  uint64_t seed_;
};

std::vector<Box> buildStaticLayout(uint64_t seed) {
  Builder B(seed);
  using V = Eigen::Vector3d;
  Box& room = B.add("room", V(0, 0, 1.5), V(3.0, 2.5, 1.5), 0, Material::kWall);
  room.inward = true;
  room.materials[4] = Material::kFloor;
  room.materials[5] = Material::kCeiling;

  // Shelf against the north wall: x in [-1.9, -0.5], y in [2.1, 2.5], 1.9 m high.
  B.add("shelf/left", V(-1.885, 2.3, 0.95), V(0.015, 0.2, 0.95), 0, Material::kWood);
  B.add("shelf/right", V(-0.515, 2.3, 0.95), V(0.015, 0.2, 0.95), 0, Material::kWood);
  B.add("shelf/back", V(-1.2, 2.49, 0.95), V(0.67, 0.01, 0.95), 0, Material::kWood);
  const double boards[] = {0.06, 0.52, 0.98, 1.44};
  for (int i = 0; i < 4; ++i)
    B.add("shelf/board" + std::to_string(i), V(-1.2, 2.3, boards[i]), V(0.67, 0.19, 0.015), 0, Material::kWood);
  B.add("shelf/top", V(-1.2, 2.29, 1.885), V(0.72, 0.21, 0.015), 0, Material::kWood);
  B.add("shelf/box", V(-1.6, 2.3, 0.655), V(0.12, 0.15, 0.12), 0, Material::kCardboard);
  B.add("shelf/books", V(-1.05, 2.32, 0.645), V(0.2, 0.1, 0.11), 0, Material::kPoster);
  B.add("shelf/box2", V(-0.85, 2.28, 1.145), V(0.16, 0.16, 0.15), 8, Material::kCardboard);
  B.add("shelf/books2", V(-1.45, 2.3, 1.555), V(0.25, 0.12, 0.1), 0, Material::kPoster);

  // Table, yawed 10 degrees, top at 0.75 m, with two things on it.
  const SE3 T_w_table(yawQ(10 * kDeg), V(1.5, 1.45, 0));
  B.addRelative("table/top", T_w_table, V(0, 0, 0.725), V(0.7, 0.4, 0.025), 0, Material::kWood);
  for (int i = 0; i < 4; ++i)
    B.addRelative("table/leg" + std::to_string(i), T_w_table, V(i < 2 ? -0.62 : 0.62, i % 2 ? 0.32 : -0.32, 0.35),
                  V(0.03, 0.03, 0.35), 0, Material::kWood);
  B.addRelative("table/box", T_w_table, V(-0.3, 0.05, 0.85), V(0.15, 0.12, 0.1), 25, Material::kCardboard);
  B.addRelative("table/book", T_w_table, V(0.35, -0.1, 0.81), V(0.12, 0.18, 0.06), -15, Material::kPoster);

  // Cabinet against the east wall with two doors and handles, a box on top.
  B.add("cabinet/body", V(2.72, 0.35, 0.55), V(0.28, 0.55, 0.55), 0, Material::kWood);
  B.add("cabinet/door0", V(2.43, 0.075, 0.55), V(0.01, 0.26, 0.5), 0, Material::kWood);
  B.add("cabinet/door1", V(2.43, 0.625, 0.55), V(0.01, 0.26, 0.5), 0, Material::kWood);
  B.add("cabinet/handle0", V(2.41, 0.28, 0.7), V(0.01, 0.015, 0.08), 0, Material::kHair);
  B.add("cabinet/handle1", V(2.41, 0.42, 0.7), V(0.01, 0.015, 0.08), 0, Material::kHair);
  B.add("cabinet/box", V(2.75, 0.2, 1.25), V(0.18, 0.2, 0.15), 15, Material::kCardboard);

  // Boxes in the north-west corner, a crate by the west wall, a box by the north wall.
  B.add("boxes/bottom", V(-2.5, 1.95, 0.25), V(0.3, 0.3, 0.25), 0, Material::kCardboard);
  B.add("boxes/top", V(-2.45, 1.9, 0.65), V(0.2, 0.18, 0.15), 20, Material::kCardboard);
  B.add("crate", V(-2.6, -0.3, 0.3), V(0.35, 0.45, 0.3), 0, Material::kWood);
  B.add("floor_box", V(0.0, 2.2, 0.2), V(0.25, 0.2, 0.2), -12, Material::kCardboard);

  // Sofa against the south wall.
  B.add("sofa/seat", V(0.4, -2.1, 0.22), V(0.9, 0.4, 0.22), 0, Material::kShirt);
  B.add("sofa/back", V(0.4, -2.4, 0.69), V(0.9, 0.1, 0.25), 0, Material::kShirt);
  B.add("sofa/arm0", V(-0.45, -2.05, 0.54), V(0.05, 0.35, 0.1), 0, Material::kShirt);
  B.add("sofa/arm1", V(1.25, -2.05, 0.54), V(0.05, 0.35, 0.1), 0, Material::kShirt);

  // A door and pictures on the walls (thin boxes: real depth edges).
  B.add("door", V(-2.99, -1.6, 1.02), V(0.01, 0.45, 1.02), 0, Material::kWood);
  B.add("picture/east", V(2.99, -1.5, 1.55), V(0.01, 0.45, 0.35), 0, Material::kPoster);
  B.add("picture/north", V(1.3, 2.49, 1.6), V(0.5, 0.01, 0.35), 0, Material::kPoster);
  B.add("picture/south", V(-1.5, -2.49, 1.5), V(0.6, 0.01, 0.4), 0, Material::kPoster);
  B.add("picture/west", V(-2.99, 1.0, 1.6), V(0.01, 0.4, 0.3), 0, Material::kPoster);
  return B.boxes;
}

/// The walking person's body at time t: boxes in the person frame (x forward, y left,
/// z up, origin on the floor), legs and arms swinging about hip and shoulder.
std::vector<Box> personBoxes(const WalkPath& w, int instance_id, uint64_t seed, double t_s) {
  const double dir = w.period_s < 0 ? -1.0 : 1.0;
  const double omega = kTwoPi / w.period_s;
  const double th = w.phase + omega * t_s;
  const Eigen::Vector2d pos = w.centre + Eigen::Vector2d(w.a * std::cos(th), w.b * std::sin(th));
  const Eigen::Vector2d vel = dir * Eigen::Vector2d(-w.a * std::sin(th), w.b * std::cos(th));
  const double yaw = std::atan2(vel.y(), vel.x());
  const double stride = 1.3;  // metres per full leg cycle
  const double cycle = kTwoPi * std::abs(t_s / w.period_s) * ellipsePerimeter(w.a, w.b) / stride;
  const double swing = 0.35 * std::sin(cycle);
  const SE3 T_w_p(yawQ(yaw), Eigen::Vector3d(pos.x(), pos.y(), 0));

  std::vector<Box> parts;
  const uint64_t body_seed = hash3(seed, 0x9e75, static_cast<uint64_t>(instance_id));
  auto add = [&](const std::string& part, const SE3& T_p_b, const Eigen::Vector3d& half, Material m, uint64_t tex) {
    Box b;
    b.name = "person" + std::to_string(instance_id) + "/" + part;
    b.T_w_b = T_w_p * T_p_b;
    b.half_size = half;
    b.materials.fill(m);
    b.texture_seed = hash2(body_seed, tex);
    b.instance_id = instance_id;
    parts.push_back(b);
    return &parts.back();
  };
  // A limb hanging from `pivot`, rotated by `angle` about the lateral axis.
  auto limb = [&](const std::string& part, const Eigen::Vector3d& pivot, const Eigen::Vector3d& half, double angle,
                  Material m, uint64_t tex) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()));
    add(part, SE3(q, pivot + q * Eigen::Vector3d(0, 0, -half.z())), half, m, tex);
  };
  limb("leg_left", {0, 0.1, 0.86}, {0.07, 0.065, 0.43}, swing, Material::kTrousers, 1);
  limb("leg_right", {0, -0.1, 0.86}, {0.07, 0.065, 0.43}, -swing, Material::kTrousers, 2);
  add("torso", SE3(Eigen::Quaterniond::Identity(), {0, 0, 1.16}), {0.12, 0.22, 0.31}, Material::kShirt, 3);
  limb("arm_left", {0, 0.29, 1.42}, {0.055, 0.055, 0.3}, -0.8 * swing, Material::kShirt, 3);
  limb("arm_right", {0, -0.29, 1.42}, {0.055, 0.055, 0.3}, 0.8 * swing, Material::kShirt, 3);
  add("neck", SE3(Eigen::Quaterniond::Identity(), {0, 0, 1.485}), {0.045, 0.045, 0.02}, Material::kSkin, 4);
  Box* head = add("head", SE3(Eigen::Quaterniond::Identity(), {0.01, 0, 1.62}), {0.1, 0.085, 0.12}, Material::kSkin, 5);
  head->materials[0] = Material::kHair;  // back
  head->materials[5] = Material::kHair;  // top
  return parts;
}

std::vector<WalkPath> walksFor(SceneKind kind) {
  auto walk = [](double cx, double cy, double a, double b, double period, double phase) {
    WalkPath w;
    w.centre = {cx, cy};
    w.a = a;
    w.b = b;
    w.period_s = period;
    w.phase = phase;
    return w;
  };
  switch (kind) {
    case SceneKind::kDynamic:
      // One across the near floor (passing 1.3 to 2 m in front), one farther off, clockwise.
      return {walk(0.0, 0.3, 1.8, 0.25, 8.0, -0.3), walk(-1.2, 1.2, 0.6, 0.25, -6.0, 1.0)};
    case SceneKind::kCrowded: {
      // Three in file on the near track, in front of the camera from about t = 1.5 s
      // (and again every 11 s), and one farther off walking the other way.
      const double lead = -M_PI / 2 - kTwoPi * 2.0 / 11.0 + 0.25;
      return {walk(0.0, -0.55, 1.9, 0.15, 11.0, lead), walk(0.0, -0.55, 1.9, 0.15, 11.0, lead - 0.32),
              walk(0.0, -0.55, 1.9, 0.15, 11.0, lead - 0.64), walk(0.2, 0.45, 1.0, 0.2, -7.0, 0.5)};
    }
    case SceneKind::kLoopWalkers: {
      // Three in file walking north 1 to 1.3 m in front of the loop's first view (the
      // camera at (0.7, -0.2) looking east), turning back short of the table. The camera
      // pans left past them within 2 s; at 3 s all are more than 90 degrees off its axis
      // and they leave, so the return to the place (the last 2 s) is clear.
      std::vector<WalkPath> file = {walk(1.6, -0.3, 0.15, 1.0, 4.0, 0.3), walk(1.6, -0.3, 0.15, 1.0, 4.0, -0.3),
                                    walk(1.6, -0.3, 0.15, 1.0, 4.0, -0.9)};
      for (WalkPath& w : file) w.leave_s = 3.0;
      return file;
    }
    default:
      return {};
  }
}

}  // namespace

const char* sceneKindName(SceneKind kind) {
  switch (kind) {
    case SceneKind::kStatic: return "static";
    case SceneKind::kDynamic: return "dynamic";
    case SceneKind::kLoop: return "loop";
    case SceneKind::kCrowded: return "crowded";
    case SceneKind::kFast: return "fast";
    case SceneKind::kLoopWalkers: return "loop_walkers";
  }
  return "?";
}

SceneKind parseSceneKind(const std::string& name) {
  for (SceneKind k : {SceneKind::kStatic, SceneKind::kDynamic, SceneKind::kLoop, SceneKind::kCrowded, SceneKind::kFast,
                      SceneKind::kLoopWalkers})
    if (name == sceneKindName(k)) return k;
  throw ConfigError("unknown synthetic scene '" + name + "' (expected static, dynamic, loop, crowded, fast or loop_walkers)");
}

int defaultFrameCount(SceneKind kind) { return kind == SceneKind::kLoop || kind == SceneKind::kLoopWalkers ? 450 : 300; }

PinholeCamera syntheticCamera(int width, int height) {
  PinholeCamera c;
  c.name = "synthetic";
  c.width = width;
  c.height = height;
  c.fx = c.fy = 525.0 * width / 640.0;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  c.depth_scale = 5000.0;
  return c;
}

std::array<Eigen::Vector3d, 8> Box::corners() const {
  std::array<Eigen::Vector3d, 8> c;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d q((i & 1) ? half_size.x() : -half_size.x(), (i & 2) ? half_size.y() : -half_size.y(),
                            (i & 4) ? half_size.z() : -half_size.z());
    c[i] = T_w_b * q;
  }
  return c;
}

std::array<Segment3d, 12> Box::edges() const {
  const auto c = corners();
  std::array<Segment3d, 12> e;
  int n = 0;
  for (int i = 0; i < 8; ++i)
    for (int bit = 1; bit < 8; bit <<= 1)
      if (!(i & bit)) e[n++] = {c[i], c[i | bit]};
  return e;
}

double Box::signedDistance(const Eigen::Vector3d& p_w) const {
  const Eigen::Vector3d q = T_w_b.inverse() * p_w;
  const Eigen::Vector3d d = q.cwiseAbs() - half_size;
  const double outside = d.cwiseMax(0.0).norm();
  const double inside = std::min(d.maxCoeff(), 0.0);
  const double sd = outside + inside;
  return inward ? -sd : sd;
}

TimeNs Scene::frameTime(int i) const {
  const int64_t us = static_cast<int64_t>(i) * 1'000'000 / 30;
  return options_.start_ns + us * 1000;
}

SE3 Scene::cameraPoseAt(TimeNs t_ns) const {
  const double t = nsToSeconds(t_ns - options_.start_ns);
  switch (kind_) {
    case SceneKind::kFast: return fast_path_->poseAt(t);
    case SceneKind::kLoop:
    case SceneKind::kLoopWalkers: {
      const double lap_s = std::max(1, options_.frames - 1) / 30.0 / options_.laps;
      const double th = kTwoPi * t / lap_s;
      const Eigen::Vector3d p(-0.2 + 0.9 * std::cos(th), -0.2 + 0.7 * std::sin(th), 1.4 + 0.06 * std::sin(2 * th));
      return lookPose(p, th + 5 * kDeg * std::sin(2 * th), (-8 + 4 * std::sin(3 * th)) * kDeg,
                      2 * kDeg * std::sin(th));
    }
    case SceneKind::kCrowded: {
      const Eigen::Vector3d p(0.05 * wave(t, 7, 0), -1.6 + 0.05 * wave(t, 5, 1), 1.45 + 0.03 * wave(t, 4, 0));
      return lookPose(p, (85 + 12 * wave(t, 10, 0)) * kDeg, (-6 + 3 * wave(t, 8, 0)) * kDeg, 2 * kDeg * wave(t, 6, 0));
    }
    default: {
      // Hand-held: slow Lissajous motion in front of the shelf / table / cabinet corner.
      const Eigen::Vector3d p(0.35 * wave(t, 9, 0.3), -1.3 + 0.25 * wave(t, 7, 1.1), 1.45 + 0.1 * wave(t, 5, 0.5));
      return lookPose(p, (70 + 25 * wave(t, 12, 0.4)) * kDeg, (-12 + 6 * wave(t, 8, 1.3)) * kDeg,
                      3 * kDeg * wave(t, 6, 0));
    }
  }
}

Trajectory Scene::groundTruth() const {
  Trajectory out;
  out.reserve(options_.frames);
  for (int i = 0; i < options_.frames; ++i) out.push_back({frameTime(i), cameraPose(i)});
  return out;
}

TimeNs Scene::exposureNs() const {
  if (kind_ != SceneKind::kFast || !options_.fast.motion_blur) return 0;
  return static_cast<TimeNs>(std::llround(options_.fast.exposure_ms * 1e6));
}

double Scene::exposureGain(TimeNs t_ns) const { return gain_.at(nsToSeconds(t_ns - options_.start_ns)); }

std::vector<Eigen::Vector3d> Scene::staticCorners() const {
  std::vector<Eigen::Vector3d> out;
  for (const Box& b : static_boxes_)
    for (const auto& c : b.corners()) out.push_back(c);
  return out;
}

std::vector<Segment3d> Scene::staticEdges() const {
  std::vector<Segment3d> out;
  for (const Box& b : static_boxes_)
    for (const auto& e : b.edges()) out.push_back(e);
  return out;
}

std::vector<Box> Scene::movingBoxes(TimeNs t_ns) const {
  std::vector<Box> out;
  const double t = nsToSeconds(t_ns - options_.start_ns);
  for (size_t i = 0; i < walks_.size(); ++i) {
    if (t >= walks_[i].leave_s) continue;
    auto parts = personBoxes(walks_[i], moving_info_[i].instance_id, options_.seed, t);
    out.insert(out.end(), parts.begin(), parts.end());
  }
  return out;
}

std::vector<Box> Scene::boxesAt(TimeNs t_ns) const {
  std::vector<Box> out = static_boxes_;
  auto moving = movingBoxes(t_ns);
  out.insert(out.end(), moving.begin(), moving.end());
  return out;
}

double Scene::staticSurfaceDistance(const Eigen::Vector3d& p_w) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Box& b : static_boxes_) best = std::min(best, std::abs(b.signedDistance(p_w)));
  return best;
}

double Scene::surfaceDistance(const Eigen::Vector3d& p_w, TimeNs t_ns) const {
  double best = staticSurfaceDistance(p_w);
  for (const Box& b : movingBoxes(t_ns)) best = std::min(best, std::abs(b.signedDistance(p_w)));
  return best;
}

int Scene::movingObjectAt(const Eigen::Vector3d& p_w, TimeNs t_ns, double tolerance) const {
  for (const Box& b : movingBoxes(t_ns))
    if (b.signedDistance(p_w) <= tolerance) return b.instance_id;
  return 0;
}

FaceTexture makeFaceTexture(const Box& box, int face) {
  const int a = face / 2, b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
  return FaceTexture(box.materials[face], box.texture_seed * 8 + static_cast<uint64_t>(face), 2 * box.half_size[b],
                     2 * box.half_size[c]);
}

RayHit Scene::castRay(const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_w, TimeNs t_ns) const {
  return synth::castRay(boxesAt(t_ns), origin_w, dir_w);
}

RayHit castRay(const std::vector<Box>& boxes, const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_w) {
  RayHit best;
  best.distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    const SE3 T_b_w = b.T_w_b.inverse();
    const Eigen::Vector3d o = T_b_w * origin_w;
    const Eigen::Vector3d d = T_b_w.quaternion() * dir_w;
    double s = 0;
    int face = -1;
    if (!intersectBox(o.data(), d.data(), b.half_size.data(), b.inward, 1e-9, &s, &face, best.distance)) continue;
    best.hit = true;
    best.distance = s;
    best.box = static_cast<int>(i);
    best.face = face;
    best.instance_id = b.instance_id;
    Eigen::Vector3d n_b = Eigen::Vector3d::Zero();
    n_b[face / 2] = (face & 1) ? 1.0 : -1.0;
    if (b.inward) n_b = -n_b;
    best.normal = b.T_w_b.quaternion() * n_b;
  }
  if (best.hit) best.point = origin_w + best.distance * dir_w;
  else best.distance = 0;
  return best;
}

std::string Scene::describe() const {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(4);
  os << "# plslam synthetic scene (see src/synth/README.md). World: metres, z up, floor z=0.\n"
     << "# box lines: name material(-x,+x,-y,+y,-z,+z faces) centre(x y z) half_size(x y z) quaternion(x y z w)\n"
     << "# person lines: instance_id class_id class_name walk centre(x y) semi_axes(a b) period_s phase_rad\n"
     << "scene " << sceneKindName(kind_) << "\n"
     << "seed " << options_.seed << "\n"
     << "frames " << options_.frames << "\n";
  if (options_.laps != 1) os << "laps " << options_.laps << "\n";  // absent for one lap: older scene.txt files still match
  os << "rate_hz 30\n"
     << "camera " << camera_.name << " " << camera_.width << "x" << camera_.height << " fx " << camera_.fx << " fy "
     << camera_.fy << " cx " << camera_.cx << " cy " << camera_.cy << "\n";
  const auto& n = options_.noise;
  if (n.enabled)
    os << "noise depth_sigma " << n.sigma_k << "*z^2 quantum " << n.quantum_m << " dropout " << n.dropout_fraction
       << " grazing_cos " << n.grazing_cos << " edge_jump " << n.edge_jump_m << " range " << n.min_depth_m << ".."
       << n.max_depth_m << " colour_sigma " << n.colour_sigma << "\n";
  else
    os << "noise off\n";
  if (kind_ == SceneKind::kFast) {
    const auto& f = options_.fast;
    os << "fast max_rotation_deg_s " << f.max_rotation_deg_s << " blur " << (f.motion_blur ? "on" : "off")
       << " exposure_ms " << f.exposure_ms << " blur_step_px " << f.blur_step_px << " max_subframes "
       << f.max_subframes << " gain " << (f.gain ? "on" : "off") << "\n";
  }
  for (const Box& b : static_boxes_) {
    os << "box " << b.name << " ";
    for (int f = 0; f < 6; ++f) os << (f ? "," : "") << materialName(b.materials[f]);
    const auto& t = b.T_w_b.translation();
    const auto& q = b.T_w_b.quaternion();
    os << " " << t.x() << " " << t.y() << " " << t.z() << " " << b.half_size.x() << " " << b.half_size.y() << " "
       << b.half_size.z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w() << (b.inward ? " inward" : "")
       << "\n";
  }
  for (size_t i = 0; i < walks_.size(); ++i) {
    const auto& w = walks_[i];
    const auto& m = moving_info_[i];
    os << "person " << m.instance_id << " " << m.class_id << " " << m.class_name << " walk " << w.centre.x() << " "
       << w.centre.y() << " " << w.a << " " << w.b << " " << w.period_s << " " << w.phase;
    if (std::isfinite(w.leave_s)) os << " leaves_s " << w.leave_s;  // absent when never: older scene.txt files still match
    os << "\n";
  }
  return os.str();
}

SE3 twinShelfTransform() {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ())), Eigen::Vector3d(0.95, 0, 0));
}

namespace {
/// Copies of the shelf's boxes and books (names "twin_shelf/...", same sizes, materials and
/// texture seeds, so the same textures), without the shelf, put on the floor by the south
/// wall in another arrangement.
void addTwinShelf(std::vector<Box>* boxes) {
  // New centres in the original shelf's frame (the world before the transform).
  const std::map<std::string, Eigen::Vector3d> moved = {{"shelf/box2", {-1.5, 2.3, 0.15}},
                                                        {"shelf/books", {-1.5, 2.32, 0.41}},
                                                        {"shelf/box", {-1.0, 2.25, 0.12}},
                                                        {"shelf/books2", {-0.6, 2.3, 0.1}}};
  const SE3 T = twinShelfTransform();
  std::vector<Box> twins;
  for (const Box& b : *boxes) {
    const auto m = moved.find(b.name);
    if (m == moved.end()) continue;
    Box t = b;
    t.name = "twin_" + b.name;
    t.T_w_b = T * SE3(b.T_w_b.quaternion(), m->second);
    twins.push_back(t);
  }
  boxes->insert(boxes->end(), twins.begin(), twins.end());
}
}  // namespace

Scene makeScene(SceneKind kind, const SceneOptions& options) {
  if (options.frames < 1 || options.frames > 1'000'000)
    throw ConfigError(str("synthetic scene: frames must be in [1, 1000000], got ", options.frames));
  if (options.width < 16 || options.height < 16 || options.width > 8192 || options.height > 8192)
    throw ConfigError(str("synthetic scene: image size ", options.width, "x", options.height, " out of range"));
  if (options.laps < 1 || options.laps > 10000)
    throw ConfigError(str("synthetic scene: laps must be in [1, 10000], got ", options.laps));
  if (options.aa_samples < 1 || options.aa_samples > 16)
    throw ConfigError(str("synthetic scene: aa_samples must be in [1, 16], got ", options.aa_samples));
  const auto& n = options.noise;
  if (!(n.sigma_k >= 0) || !(n.quantum_m >= 0) || !(n.dropout_fraction >= 0 && n.dropout_fraction <= 1) ||
      !(n.min_depth_m >= 0 && n.max_depth_m > n.min_depth_m) || !(n.colour_sigma >= 0))
    throw ConfigError("synthetic scene: depth noise options out of range");
  const auto& fast = options.fast;
  if (!(fast.max_rotation_deg_s >= 1 && fast.max_rotation_deg_s <= 2000) || !(fast.exposure_ms >= 0 && fast.exposure_ms <= 33) ||
      !(fast.blur_step_px >= 0.1) || fast.max_subframes < 1 || fast.max_subframes > 256)
    throw ConfigError("synthetic scene: fast motion options out of range (rotation 1..2000 deg/s, exposure 0..33 ms, "
                      "blur step >= 0.1 px, 1..256 sub-frames)");
  Scene s;
  s.kind_ = kind;
  s.options_ = options;
  s.camera_ = syntheticCamera(options.width, options.height);
  s.static_boxes_ = buildStaticLayout(options.seed);
  if (options.twin_shelf) addTwinShelf(&s.static_boxes_);
  for (const Box& b : s.static_boxes_) {
    std::array<std::shared_ptr<const FaceTexture>, 6> faces;
    for (int f = 0; f < 6; ++f) faces[f] = std::make_shared<const FaceTexture>(makeFaceTexture(b, f));
    s.static_textures_.push_back(faces);
  }
  s.walks_ = walksFor(kind);
  for (size_t i = 0; i < s.walks_.size(); ++i) s.moving_info_.push_back({static_cast<int>(i) + 1, 0, "person"});
  if (kind == SceneKind::kFast) {
    s.fast_path_.emplace(fast.max_rotation_deg_s);
    if (fast.gain) s.gain_ = ExposureGain(options.seed, options.frames / 30.0 + 1.0);
  }
  return s;
}

}  // namespace plslam::synth
