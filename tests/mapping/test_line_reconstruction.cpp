// Line reconstruction on analytic depth images: a box in front of a tilted wall, depth computed
// per pixel by exact ray intersections, box edges projected to get the 2D segments.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/error.h"
#include "mapping/line_reconstruction.h"

namespace plslam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

PinholeCamera idealCamera() {
  PinholeCamera cam;
  cam.name = "test_525";
  cam.width = 640;
  cam.height = 480;
  cam.fx = cam.fy = 525.0;
  cam.cx = 319.5;
  cam.cy = 239.5;
  return cam;
}

PinholeCamera distortedCamera() {  // TUM freiburg1 colour camera
  PinholeCamera cam = idealCamera();
  cam.name = "tum_freiburg1";
  cam.fx = 517.3;
  cam.fy = 516.5;
  cam.cx = 318.6;
  cam.cy = 255.3;
  cam.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  return cam;
}

struct Edge {
  Eigen::Vector3d A, B;  ///< true 3D endpoints, camera frame
  bool silhouette = false;
};

/// A tilted wall about 3 m away and a rotated box about 1.6 m away, in the camera frame.
struct BoxScene {
  PinholeCamera cam;
  Eigen::Vector3d wall_point{0.0, 0.0, 3.0};
  Eigen::Vector3d wall_normal = Eigen::Vector3d(0.1, 0.05, -1.0).normalized();
  Eigen::Vector3d box_center{0.05, 0.0, 1.6};
  Eigen::Vector3d box_half{0.25, 0.18, 0.2};
  Eigen::Matrix3d R_c_b;  ///< box orientation
  cv::Mat depth;          ///< exact depth, CV_32F metres

  explicit BoxScene(const PinholeCamera& camera) : cam(camera) {
    R_c_b = (Eigen::AngleAxisd(35 * M_PI / 180, Eigen::Vector3d::UnitY()) *
             Eigen::AngleAxisd(-25 * M_PI / 180, Eigen::Vector3d::UnitX()))
                .toRotationMatrix();
    depth = cv::Mat(cam.height, cam.width, CV_32FC1);
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d ray = cam.unproject(Eigen::Vector2d(u, v), 1.0);  // z = 1
        const double z = std::min(boxHit(ray), wallHit(ray));
        depth.at<float>(v, u) = std::isfinite(z) ? static_cast<float>(z) : std::nanf("");
      }
  }

  /// Depth (ray parameter for a z = 1 ray) of the box's first hit, +inf when missed.
  double boxHit(const Eigen::Vector3d& ray) const {
    const Eigen::Vector3d o = R_c_b.transpose() * (-box_center), d = R_c_b.transpose() * ray;
    double t0 = -kInf, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(d[a]) < 1e-15) {
        if (std::abs(o[a]) > box_half[a]) return kInf;
        continue;
      }
      double ta = (-box_half[a] - o[a]) / d[a], tb = (box_half[a] - o[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return (t0 <= t1 && t0 > 0) ? t0 : kInf;
  }
  double wallHit(const Eigen::Vector3d& ray) const {
    const double den = wall_normal.dot(ray);
    const double t = wall_normal.dot(wall_point) / den;
    return (std::abs(den) > 1e-12 && t > 0) ? t : kInf;
  }
  double sceneDepth(const Eigen::Vector3d& ray) const { return std::min(boxHit(ray), wallHit(ray)); }
  double wallDistance(const Eigen::Vector3d& x) const { return std::abs(wall_normal.dot(x - wall_point)); }
  bool visible(const Eigen::Vector3d& x) const { return sceneDepth(x / x.z()) >= x.z() - 1e-6; }

  /// The box edges whose whole length is visible, classified as silhouette (the wall on one
  /// side) or face edge (box on both sides).
  std::vector<Edge> visibleEdges() const {
    std::vector<Eigen::Vector3d> corners;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d s((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
      corners.push_back(box_center + R_c_b * s.cwiseProduct(box_half));
    }
    std::vector<Edge> edges;
    for (int i = 0; i < 8; ++i)
      for (int bit : {1, 2, 4}) {
        if (i & bit) continue;
        Edge e{corners[i], corners[i | bit], false};
        bool all_visible = true;
        for (int k = 1; k < 20; ++k) all_visible &= visible(e.A + (e.B - e.A) * (k / 20.0));
        if (!all_visible) continue;
        const Eigen::Vector2d a = cam.project(e.A), b = cam.project(e.B), m = cam.project(0.5 * (e.A + e.B));
        const Eigen::Vector2d n = Eigen::Vector2d(-(b - a).y(), (b - a).x()).normalized();
        for (double side : {-4.0, 4.0})
          e.silhouette |= !std::isfinite(boxHit(cam.unproject(m + side * n, 1.0)));
        edges.push_back(e);
      }
    return edges;
  }
  /// Unit image normal of the edge pointing to the wall side (silhouette edges only).
  Eigen::Vector2d wallSide(const Edge& e) const {
    const Eigen::Vector2d a = cam.project(e.A), b = cam.project(e.B), m = cam.project(0.5 * (e.A + e.B));
    const Eigen::Vector2d n = Eigen::Vector2d(-(b - a).y(), (b - a).x()).normalized();
    return std::isfinite(boxHit(cam.unproject(m + 4.0 * n, 1.0))) ? Eigen::Vector2d(-n) : n;
  }
};

/// Kinect-like noise (sigma = 0.0015 z^2) and random dropouts, seeded.
cv::Mat noisy(const cv::Mat& depth, unsigned seed, double dropout) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  cv::Mat out = depth.clone();
  for (int v = 0; v < out.rows; ++v)
    for (int u = 0; u < out.cols; ++u) {
      float& z = out.at<float>(v, u);
      const double g = gauss(rng), drop = uni(rng);
      if (!std::isfinite(z)) continue;
      z = drop < dropout ? std::nanf("") : static_cast<float>(z + 0.0015 * z * z * g);
    }
  return out;
}

double distanceToLine(const Eigen::Vector3d& x, const Eigen::Vector3d& A, const Eigen::Vector3d& B) {
  return (x - A).cross((B - A).normalized()).norm();
}

/// Asserts the estimate lies on the true line (max endpoint distance) and its endpoints are
/// near the true ones.
void expectNear(const LineSegment3D& s, const Eigen::Vector3d& A, const Eigen::Vector3d& B, double line_tol,
                double end_tol, const std::string& what) {
  EXPECT_LE(distanceToLine(s.P_c, A, B), line_tol) << what;
  EXPECT_LE(distanceToLine(s.Q_c, A, B), line_tol) << what;
  EXPECT_LE((s.P_c - A).norm(), end_tol) << what;
  EXPECT_LE((s.Q_c - B).norm(), end_tol) << what;
}

std::string describe(const Edge& e, int i) {
  return "edge " + std::to_string(i) + (e.silhouette ? " (silhouette)" : " (face)");
}

class FitOnBoxScene : public ::testing::TestWithParam<bool> {};  // param: distorted camera

TEST_P(FitOnBoxScene, NoiseFreeFitRecoversFaceAndSilhouetteEdgesWithin1cm) {
  const BoxScene scene(GetParam() ? distortedCamera() : idealCamera());
  const std::vector<Edge> edges = scene.visibleEdges();
  int silhouettes = 0, faces = 0;
  for (size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    (e.silhouette ? silhouettes : faces)++;
    LineFitDiagnostics diag;
    const auto seg = fitLine3D(scene.cam.project(e.A), scene.cam.project(e.B), scene.depth, scene.cam, {}, &diag);
    ASSERT_TRUE(seg.has_value()) << describe(e, i) << ": " << toString(diag.status);
    EXPECT_EQ(diag.status, LineFitStatus::kOk);
    EXPECT_GE(seg->inliers, 8);
    expectNear(*seg, e.A, e.B, 0.01, 0.02, describe(e, i));
  }
  EXPECT_GE(silhouettes, 2);  // the scene must exercise both kinds of edge
  EXPECT_GE(faces, 2);
}

TEST_P(FitOnBoxScene, KinectNoiseAndDropoutsStayWithin1cmOfTheLine) {
  const BoxScene scene(GetParam() ? distortedCamera() : idealCamera());
  const std::vector<Edge> edges = scene.visibleEdges();
  ASSERT_GE(edges.size(), 4u);
  for (unsigned seed : {1u, 2u, 3u}) {
    const cv::Mat depth = noisy(scene.depth, seed, 0.10);
    for (size_t i = 0; i < edges.size(); ++i) {
      const Edge& e = edges[i];
      LineFitDiagnostics diag;
      const auto seg = fitLine3D(scene.cam.project(e.A), scene.cam.project(e.B), depth, scene.cam, {}, &diag);
      ASSERT_TRUE(seg.has_value()) << describe(e, i) << " seed " << seed << ": " << toString(diag.status);
      expectNear(*seg, e.A, e.B, 0.01, 0.015, describe(e, i) + " seed " + std::to_string(seed));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cameras, FitOnBoxScene, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& param) { return param.param ? "Distorted" : "Ideal"; });

TEST(LineReconstruction, SilhouetteEdgeIsReconstructedOnTheNearSurface) {
  const BoxScene scene(idealCamera());
  int tested = 0;
  for (const Edge& e : scene.visibleEdges()) {
    if (!e.silhouette) continue;
    // The detected segment lies 1 px on the wall side of the true edge, as LSD often puts it.
    const Eigen::Vector2d shift = scene.wallSide(e);
    const Eigen::Vector2d p = scene.cam.project(e.A) + shift, q = scene.cam.project(e.B) + shift;
    const Eigen::Vector2d mid = 0.5 * (p + q);
    ASSERT_GT(depthAt(scene.depth, mid.x(), mid.y()), 2.5) << "the shifted segment should sit on the wall";

    const auto seg = fitLine3D(p, q, scene.depth, scene.cam, {});
    ASSERT_TRUE(seg.has_value());
    expectNear(*seg, e.A, e.B, 0.01, 0.02, "shifted silhouette edge");
    EXPECT_GT(scene.wallDistance(0.5 * (seg->P_c + seg->Q_c)), 0.5);

    // Without the perpendicular search the same segment lands on the wall (or is refused).
    LineFitOptions exact;
    exact.perp_search_px = 0;
    const auto on_wall = fitLine3D(p, q, scene.depth, scene.cam, exact);
    if (on_wall) {
      EXPECT_GT(distanceToLine(0.5 * (on_wall->P_c + on_wall->Q_c), e.A, e.B), 0.3);
    }
    ++tested;
  }
  EXPECT_GE(tested, 2);
}

/// A face edge's 20%..80% part: both endpoints well inside the box's image, so that the
/// endpoint method works on clean depth.
Edge innerFacePart(const BoxScene& scene) {
  for (const Edge& e : scene.visibleEdges())
    if (!e.silhouette) return {e.A + 0.2 * (e.B - e.A), e.A + 0.8 * (e.B - e.A), false};
  ADD_FAILURE() << "no face edge";
  return {};
}

TEST(LineReconstruction, EndpointMethodFailsOnADepthHoleWhileFittingSucceeds) {
  const BoxScene scene(idealCamera());
  const Edge e = innerFacePart(scene);
  const Eigen::Vector2d p = scene.cam.project(e.A), q = scene.cam.project(e.B);
  const LineFitOptions opt;

  const auto clean = backprojectEndpoints(p, q, scene.depth, scene.cam, opt);
  ASSERT_TRUE(clean.has_value()) << "the endpoint method must work on clean depth";
  expectNear(*clean, e.A, e.B, 0.01, 0.02, "endpoint method, clean");

  cv::Mat holed = scene.depth.clone();
  holed(cv::Rect(static_cast<int>(p.x()) - 4, static_cast<int>(p.y()) - 4, 9, 9)).setTo(std::nanf(""));
  LineFitDiagnostics diag;
  EXPECT_FALSE(backprojectEndpoints(p, q, holed, scene.cam, opt, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kEndpointDepthMissing);

  const auto fit = fitLine3D(p, q, holed, scene.cam, opt, &diag);
  ASSERT_TRUE(fit.has_value()) << toString(diag.status);
  EXPECT_LT(diag.valid_samples, diag.samples);
  expectNear(*fit, e.A, e.B, 0.01, 0.02, "fit over a hole");
}

TEST(LineReconstruction, EndpointMethodFailsWhenAnEndpointOvershootsOntoTheWall) {
  const BoxScene scene(idealCamera());
  int tested = 0;
  for (const Edge& e : scene.visibleEdges()) {
    if (!e.silhouette) continue;
    // Run the segment 2 px inside the box along the silhouette edge, from 20% of the edge...
    const Eigen::Vector2d in = -2.0 * scene.wallSide(e);
    const Eigen::Vector3d A = e.A + 0.2 * (e.B - e.A);
    const Eigen::Vector2d p = scene.cam.project(A) + in, b = scene.cam.project(e.B) + in;
    const auto inside = backprojectEndpoints(p, b - 6.0 * (b - p).normalized(), scene.depth, scene.cam, {});
    ASSERT_TRUE(inside.has_value()) << "the endpoint method must work inside the box";
    // ...and let it overshoot the corner onto the wall (the first point past the corner
    // whose 3x3 neighbourhood is all wall, plus a pixel).
    const Eigen::Vector2d dir = (b - p).normalized();
    double over = 1;
    auto onWall = [&](const Eigen::Vector2d& x) {
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (!(depthAt(scene.depth, x.x() + dx, x.y() + dy) > 2.5)) return false;
      return true;
    };
    while (over < 20 && !onWall(b + over * dir)) over += 1;
    ASSERT_LT(over, 20) << "the overshooting endpoint should reach the wall";
    const Eigen::Vector2d q = b + (over + 1) * dir;

    LineFitDiagnostics diag;
    const auto ends = backprojectEndpoints(p, q, scene.depth, scene.cam, {}, &diag);
    EXPECT_FALSE(ends.has_value());
    EXPECT_EQ(diag.status, LineFitStatus::kMidpointDepthMismatch);

    const auto fit = fitLine3D(p, q, scene.depth, scene.cam, {}, &diag);
    ASSERT_TRUE(fit.has_value()) << toString(diag.status);
    EXPECT_LT(diag.inliers, diag.valid_samples);  // the wall samples were rejected
    // The true line: where the rays through the 2D segment meet the box face, 2 px inside the
    // edge (through p and the 2D midpoint: near the corner the shifted line may graze the
    // neighbouring face).
    const Eigen::Vector3d ray_p = scene.cam.unproject(p, 1.0), ray_m = scene.cam.unproject(0.5 * (p + b), 1.0);
    const Eigen::Vector3d ray_b = scene.cam.unproject(b, 1.0);
    const Eigen::Vector3d A_in = ray_p * scene.boxHit(ray_p), M_in = ray_m * scene.boxHit(ray_m);
    const Eigen::Vector3d B_in = ray_b * scene.boxHit(ray_b);
    EXPECT_LE(distanceToLine(fit->P_c, A_in, M_in), 0.01);
    EXPECT_LE(distanceToLine(fit->Q_c, A_in, M_in), 0.01);
    EXPECT_LE((fit->P_c - A_in).norm(), 0.02);
    // Q follows the overshooting 2D endpoint a few pixels past the corner.
    EXPECT_LE((fit->Q_c - B_in).norm(), 0.01 + (over + 1) * B_in.z() / scene.cam.fx * 2);
    ++tested;
  }
  EXPECT_GE(tested, 2);
}

TEST(LineReconstruction, SegmentWithoutDepthIsRefused) {
  const PinholeCamera cam = idealCamera();
  const cv::Mat none(cam.height, cam.width, CV_32FC1, cv::Scalar(std::nanf("")));
  const Eigen::Vector2d p(100, 100), q(300, 200);
  LineFitDiagnostics diag;
  EXPECT_FALSE(fitLine3D(p, q, none, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kTooFewDepthSamples);
  EXPECT_EQ(diag.valid_samples, 0);
  EXPECT_FALSE(backprojectEndpoints(p, q, none, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kEndpointDepthMissing);

  // A hole in otherwise valid depth, out-of-range depth, and segments leaving the image.
  const BoxScene scene(cam);
  cv::Mat holed = scene.depth.clone();
  holed(cv::Rect(50, 50, 300, 200)).setTo(std::nanf(""));
  EXPECT_FALSE(fitLine3D(p, q, holed, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kTooFewDepthSamples);
  const cv::Mat too_far(cam.height, cam.width, CV_32FC1, cv::Scalar(9.0f));
  EXPECT_FALSE(fitLine3D(p, q, too_far, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kTooFewDepthSamples);
  EXPECT_FALSE(fitLine3D({-500, -500}, {-100, -300}, scene.depth, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kTooFewDepthSamples);
  EXPECT_NO_THROW((void)fitLine3D({-200, 240}, {600, 240}, scene.depth, cam, {}));  // half outside
  EXPECT_FALSE(fitLine3D(p, p, scene.depth, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kSegmentTooShort);

  EXPECT_THROW(fitLine3D(p, q, cv::Mat(), cam, {}), DataError);
  EXPECT_THROW(fitLine3D(p, q, cv::Mat(480, 640, CV_16UC1), cam, {}), DataError);
}

TEST(LineReconstruction, SegmentSeenEndOnIsRejected) {
  const PinholeCamera cam = idealCamera();
  // A 3 m line 5 degrees off the viewing ray of its near end, on a plane that contains it
  // and faces the line's interpretation plane (so the depth across the segment is smooth).
  const Eigen::Vector3d A(0.3, 0.2, 1.0);
  const Eigen::Vector3d axis = A.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d d = (Eigen::AngleAxisd(5 * M_PI / 180, axis) * A.normalized()).normalized();
  const Eigen::Vector3d B = A + 3.0 * d;
  const Eigen::Vector3d n = (A - A.dot(d) * d).normalized();
  cv::Mat depth(cam.height, cam.width, CV_32FC1);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d ray = cam.unproject(Eigen::Vector2d(u, v), 1.0);
      const double t = n.dot(A) / n.dot(ray);
      depth.at<float>(v, u) = (t > 0 && t < 20) ? static_cast<float>(t) : std::nanf("");
    }
  const Eigen::Vector2d p = cam.project(A), q = cam.project(B);
  ASSERT_GT((q - p).norm(), 20.0) << "the end-on segment must still be long enough to be tried";

  LineFitDiagnostics diag;
  EXPECT_FALSE(fitLine3D(p, q, depth, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kDegenerateViewingRay);
  EXPECT_FALSE(backprojectEndpoints(p, q, depth, cam, {}, &diag).has_value());
  EXPECT_EQ(diag.status, LineFitStatus::kDegenerateViewingRay);

  // The rejection is the angle test's doing: with a smaller limit the same line is accepted
  // (its far end is only about 1.3 degrees off its viewing ray).
  LineFitOptions lax;
  lax.min_view_angle_deg = 0.5;
  const auto seg = fitLine3D(p, q, depth, cam, lax, &diag);
  ASSERT_TRUE(seg.has_value()) << toString(diag.status);
  EXPECT_LE(distanceToLine(seg->P_c, A, B), 0.02);
  EXPECT_LE(distanceToLine(seg->Q_c, A, B), 0.02);
}

TEST(LineReconstruction, ImplausibleLengthIsRejected) {
  const BoxScene scene(idealCamera());
  const Edge e = scene.visibleEdges().front();
  LineFitOptions opt;
  opt.max_length_m = 0.5 * (e.B - e.A).norm();
  LineFitDiagnostics diag;
  EXPECT_FALSE(fitLine3D(scene.cam.project(e.A), scene.cam.project(e.B), scene.depth, scene.cam, opt, &diag));
  EXPECT_EQ(diag.status, LineFitStatus::kImplausibleLength);
}

TEST(LineReconstruction, RateAveragesPerFrameAndSkipsEmptyFrames) {
  LineReconstructionRate rate;
  EXPECT_EQ(rate.average(), 0.0);
  rate.add(3, 4);
  rate.add(0, 0);  // no segment used: not a frame of the average
  rate.add(1, 2);
  rate.add(10, 10);
  EXPECT_EQ(rate.frames(), 3);
  EXPECT_DOUBLE_EQ(rate.average(), (0.75 + 0.5 + 1.0) / 3);
  EXPECT_EQ(rate.totalBuilt(), 14);
  EXPECT_EQ(rate.totalUsed(), 16);
  EXPECT_NE(rate.average(), 14.0 / 16.0);  // per-frame mean, not the pooled ratio
  EXPECT_THROW(rate.add(3, 2), DataError);
  EXPECT_THROW(rate.add(-1, 2), DataError);
}

TEST(LineReconstruction, OptionsValidation) {
  EXPECT_NO_THROW(LineFitOptions{}.validate());
  auto bad = [](auto mutate) {
    LineFitOptions o;
    mutate(o);
    EXPECT_THROW(o.validate(), ConfigError);
  };
  bad([](LineFitOptions& o) { o.sample_step_px = 0; });
  bad([](LineFitOptions& o) { o.max_depth_m = 0.05; });
  bad([](LineFitOptions& o) { o.min_inlier_ratio = 1.5; });
  bad([](LineFitOptions& o) { o.perp_search_px = -1; });
  bad([](LineFitOptions& o) { o.min_view_angle_deg = 90; });
  bad([](LineFitOptions& o) { o.min_inliers = 1; });
}

}  // namespace
}  // namespace plslam
