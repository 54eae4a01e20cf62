#include "synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace plslam::test {

namespace {

double uniform(std::mt19937& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
double gauss(std::mt19937& rng, double sigma) {
  return sigma > 0.0 ? std::normal_distribution<double>(0.0, sigma)(rng) : 0.0;
}

bool visible(const PinholeCamera& cam, const SE3& T_w_c, const Eigen::Vector3d& p_w, double border = 5.0) {
  const Eigen::Vector3d p_c = T_w_c.inverse() * p_w;
  return p_c.z() > 0.5 && cam.inImage(cam.projectIdeal(p_c), border);
}

const double kScale = 1.2;  // the default MeasurementModel::scale_factor

}  // namespace

PinholeCamera syntheticCamera() {
  PinholeCamera cam;
  cam.name = "synthetic";
  cam.width = 640, cam.height = 480;
  cam.fx = 517.3, cam.fy = 516.5, cam.cx = 318.6, cam.cy = 255.3;
  return cam;
}

SE3 pathPose(int k, int n) {
  // An S-shaped sweep about 1.5 m wide and 0.8 m high, so the camera centres are far from
  // collinear and 3D lines of any direction are triangulable.
  const double t = n > 1 ? -1.0 + 2.0 * k / (n - 1) : 0.0;
  const Eigen::Vector3d c(0.9 * std::sin(t), 0.4 * std::sin(2.5 * t), 0.1 * t);
  const Eigen::Vector3d target(0.0, 0.0, 3.5);
  const Eigen::Vector3d z = (target - c).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, 1, 0).cross(z).normalized();  // world +y is "down"
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  return SE3(R, c);
}

Eigen::Vector3d randomUnit(std::mt19937& rng) {
  Eigen::Vector3d v(gauss(rng, 1.0), gauss(rng, 1.0), gauss(rng, 1.0));
  return v.normalized();
}

SE3 perturb(const SE3& T, double trans_m, double angle_deg, std::mt19937& rng) {
  const Eigen::Quaterniond dq(Eigen::AngleAxisd(angle_deg * M_PI / 180.0, randomUnit(rng)));
  return T * SE3(dq, trans_m * randomUnit(rng));
}

double distanceToLine(const Eigen::Vector3d& X, const Eigen::Vector3d& P, const Eigen::Vector3d& Q) {
  const Eigen::Vector3d d = (Q - P).normalized();
  return (X - P).cross(d).norm();
}

std::vector<Eigen::Vector3d> pointsInView(const PinholeCamera& cam, const SE3& T_w_c, int n, double zmin,
                                          double zmax, std::mt19937& rng) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d uv(uniform(rng, 10, cam.width - 11), uniform(rng, 10, cam.height - 11));
    out.push_back(T_w_c * cam.unprojectIdeal(uv, uniform(rng, zmin, zmax)));
  }
  return out;
}

std::vector<Segment3> segmentsInView(const PinholeCamera& cam, const std::vector<SE3>& T_w_c, int n, double zmin,
                                     double zmax, std::mt19937& rng, double min_length_px,
                                     double min_plane_angle_deg) {
  std::vector<Segment3> out;
  for (int attempt = 0; attempt < 1000 * n && static_cast<int>(out.size()) < n; ++attempt) {
    const Eigen::Vector3d c = pointsInView(cam, T_w_c.front(), 1, zmin, zmax, rng).front();
    const Eigen::Vector3d d = randomUnit(rng);
    const double half = 0.5 * uniform(rng, 0.4, 1.2);
    const Segment3 S{c - half * d, c + half * d};
    bool ok = true;
    for (const SE3& T : T_w_c) {  // the observed extent reaches 10% beyond the endpoints
      ok = ok && visible(cam, T, S.P - 0.1 * (S.Q - S.P)) && visible(cam, T, S.Q + 0.1 * (S.Q - S.P));
      // Well-conditioned lines only, as a mapper would keep: long in the image and not
      // seen end-on (the 3D direction of a short or end-on segment is poorly observed).
      const Eigen::Vector3d P_c = T.inverse() * S.P, Q_c = T.inverse() * S.Q;
      const double sin_view = (Q_c - P_c).normalized().cross((0.5 * (P_c + Q_c)).normalized()).norm();
      ok = ok && P_c.z() > 0 && Q_c.z() > 0 && sin_view > 0.5 &&
           (cam.projectIdeal(P_c) - cam.projectIdeal(Q_c)).norm() > min_length_px;
    }
    // Triangulable: the planes through the line and the camera centres must span a wide
    // enough angle about the line (as a mapper's triangulation-angle check would demand).
    double widest = 0.0;
    for (const SE3& A : T_w_c)
      for (const SE3& B : T_w_c) {
        const Eigen::Vector3d na = (S.P - A.translation()).cross(S.Q - A.translation()).normalized();
        const Eigen::Vector3d nb = (S.P - B.translation()).cross(S.Q - B.translation()).normalized();
        widest = std::max(widest, std::acos(std::min(1.0, std::abs(na.dot(nb)))));
      }
    ok = ok && widest > min_plane_angle_deg * M_PI / 180.0;
    if (ok) out.push_back(S);
  }
  if (static_cast<int>(out.size()) < n) throw std::runtime_error("segmentsInView: could not place the segments");
  return out;
}

void observeSegment(const PinholeCamera& cam, const SE3& T_w_c, const Segment3& S, double noise_px,
                    std::mt19937& rng, Eigen::Vector2d* p, Eigen::Vector2d* q) {
  const SE3 T_c_w = T_w_c.inverse();
  const Eigen::Vector3d A = S.P + uniform(rng, -0.1, 0.1) * (S.Q - S.P);
  const Eigen::Vector3d B = S.P + uniform(rng, 0.9, 1.1) * (S.Q - S.P);
  *p = cam.projectIdeal(T_c_w * A) + Eigen::Vector2d(gauss(rng, noise_px), gauss(rng, noise_px));
  *q = cam.projectIdeal(T_c_w * B) + Eigen::Vector2d(gauss(rng, noise_px), gauss(rng, noise_px));
}

PoseOnlyScene makePoseOnlyScene(const PinholeCamera& cam, int n_points, int n_lines, bool with_depth,
                                double noise_px, double depth_noise_scale, std::mt19937& rng) {
  const MeasurementModel model;
  PoseOnlyScene s;
  s.T_w_c_true = pathPose(3, 10);
  const SE3 T_c_w = s.T_w_c_true.inverse();
  for (const Eigen::Vector3d& p_w : pointsInView(cam, s.T_w_c_true, n_points, 1.0, 5.0, rng)) {
    PointObs o;
    o.p_w = p_w;
    o.octave = std::uniform_int_distribution<int>(0, 2)(rng);
    const double sigma = noise_px * std::pow(kScale, o.octave);
    const Eigen::Vector3d p_c = T_c_w * p_w;
    o.uv = cam.projectIdeal(p_c) + Eigen::Vector2d(gauss(rng, sigma), gauss(rng, sigma));
    if (with_depth) o.depth = p_c.z() + gauss(rng, depth_noise_scale * model.depthSigma(p_c.z()));
    s.problem.points.push_back(o);
  }
  for (const Segment3& S : segmentsInView(cam, {s.T_w_c_true}, n_lines, 1.0, 5.0, rng)) {
    LineObs o;
    o.P_w = S.P, o.Q_w = S.Q;
    o.octave = std::uniform_int_distribution<int>(0, 2)(rng);
    observeSegment(cam, s.T_w_c_true, S, noise_px * std::pow(kScale, o.octave), rng, &o.p, &o.q);
    s.problem.lines.push_back(o);
  }
  s.problem.T_w_c_init = s.T_w_c_true;
  return s;
}

BundleScene makeBundleScene(const PinholeCamera& cam, int n_kf, int n_points, int n_lines, bool with_depth,
                            double noise_px, std::mt19937& rng, int views_per_point,
                            double min_line_plane_angle_deg) {
  const MeasurementModel model;
  BundleScene s;
  const int views = views_per_point > 0 ? std::min(views_per_point, n_kf) : n_kf;
  for (int k = 0; k < n_kf; ++k) s.T_w_c_true.push_back(pathPose(k, n_kf));
  const SE3 middle = s.T_w_c_true[n_kf / 2];
  for (int attempt = 0; attempt < 100 * n_points && static_cast<int>(s.points_true.size()) < n_points; ++attempt) {
    const Eigen::Vector3d p = pointsInView(cam, middle, 1, 1.5, 4.5, rng).front();
    bool ok = true;
    for (const SE3& T : s.T_w_c_true) ok = ok && visible(cam, T, p);
    if (ok) s.points_true.push_back(p);
  }
  if (static_cast<int>(s.points_true.size()) < n_points) throw std::runtime_error("makeBundleScene: too few points");
  s.lines_true = segmentsInView(cam, s.T_w_c_true, n_lines, 1.2, 2.5, rng, 60.0, min_line_plane_angle_deg);

  for (int k = 0; k < n_kf; ++k) s.problem.keyframes.push_back({s.T_w_c_true[k], false});
  for (const auto& p : s.points_true) s.problem.points.push_back({p, false});
  for (const auto& l : s.lines_true) s.problem.lines.push_back({l.P, l.Q, false});
  std::vector<int> first_view(s.points_true.size());
  for (int& f : first_view) f = std::uniform_int_distribution<int>(0, n_kf - views)(rng);
  for (int k = 0; k < n_kf; ++k) {
    const SE3 T_c_w = s.T_w_c_true[k].inverse();
    for (size_t i = 0; i < s.points_true.size(); ++i) {
      if (k < first_view[i] || k >= first_view[i] + views) continue;
      BundleProblem::PointObs o;
      o.keyframe = k, o.point = static_cast<int>(i);
      o.octave = std::uniform_int_distribution<int>(0, 2)(rng);
      const double sigma = noise_px * std::pow(kScale, o.octave);
      const Eigen::Vector3d p_c = T_c_w * s.points_true[i];
      o.uv = cam.projectIdeal(p_c) + Eigen::Vector2d(gauss(rng, sigma), gauss(rng, sigma));
      if (with_depth) o.depth = p_c.z() + gauss(rng, noise_px > 0 ? model.depthSigma(p_c.z()) : 0.0);
      s.problem.point_obs.push_back(o);
    }
    for (size_t i = 0; i < s.lines_true.size(); ++i) {
      BundleProblem::LineObs o;
      o.keyframe = k, o.line = static_cast<int>(i);
      o.octave = std::uniform_int_distribution<int>(0, 2)(rng);
      observeSegment(cam, s.T_w_c_true[k], s.lines_true[i], noise_px * std::pow(kScale, o.octave), rng, &o.p, &o.q);
      s.problem.line_obs.push_back(o);
    }
  }
  return s;
}

}  // namespace plslam::test
