#include "calibration/render.h"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag36h11.h>

#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/error.h"
#include "core/log.h"

namespace plslam::calib {

namespace {

/// The 8x8 cells (black border + 6x6 data bits) of every tag of a grid, 0 = black, 1 = white,
/// taken from the apriltag library's tag36h11 family so that its detector decodes them.
std::vector<std::array<uint8_t, 64>> tagBitmaps(const Target& t) {
  std::vector<std::array<uint8_t, 64>> out;
  apriltag_family_t* fam = tag36h11_create();
  if (fam->width_at_border != 8) {
    tag36h11_destroy(fam);
    throw DataError("tag36h11: unexpected width_at_border (the renderer assumes 8 cells)");
  }
  const int border_start = (fam->total_width - fam->width_at_border) / 2;
  for (int k = 0; k < t.cols * t.rows; ++k) {
    image_u8_t* im = apriltag_to_image(fam, t.first_id + k);
    std::array<uint8_t, 64> cells{};
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) cells[y * 8 + x] = im->buf[(y + border_start) * im->stride + x + border_start] > 127;
    image_u8_destroy(im);
    out.push_back(cells);
  }
  tag36h11_destroy(fam);
  return out;
}

/// Reflectance of the board at board coordinates (x, y): 0 black .. 1 white, or -1 off the board.
class BoardTexture {
 public:
  explicit BoardTexture(const Target& t) : t_(t), printed_(t.printedArea()) {
    if (t.kind == TargetKind::kAprilGrid) tags_ = tagBitmaps(t);
  }

  float at(double x, double y) const {
    if (x < printed_.x || y < printed_.y || x >= printed_.x + printed_.width || y >= printed_.y + printed_.height)
      return -1.f;
    if (t_.kind == TargetKind::kChessboard) {
      const int i = static_cast<int>(std::floor(x / t_.size)) + 1;  // square column, 0..cols
      const int j = static_cast<int>(std::floor(y / t_.size)) + 1;
      if (i < 0 || j < 0 || i > t_.cols || j > t_.rows) return 1.f;  // white frame
      return (i + j) % 2 == 0 ? 0.f : 1.f;                           // the top-left square is black
    }
    const double pitch = t_.size + t_.spacing;
    if (x < 0 || y < 0) return 1.f;
    const int c = static_cast<int>(x / pitch), r = static_cast<int>(y / pitch);
    if (c >= t_.cols || r >= t_.rows) return 1.f;
    const double u = x - c * pitch, v = y - r * pitch;
    if (u >= t_.size || v >= t_.size) return 1.f;  // the gap between tags
    const int cx = std::min(7, static_cast<int>(u / t_.tagCell()));
    const int cy = std::min(7, static_cast<int>(v / t_.tagCell()));
    return tags_[r * t_.cols + c][cy * 8 + cx];
  }

 private:
  Target t_;
  cv::Rect2d printed_;
  std::vector<std::array<uint8_t, 64>> tags_;
};

/// Normalised image coordinates (x/z, y/z) of the ray through raw pixel (u, v).
Eigen::Vector2d rayOf(const PinholeCamera& cam, double u, double v) {
  const Eigen::Vector2d ideal = cam.undistort({u, v});
  return {(ideal.x() - cam.cx) / cam.fx, (ideal.y() - cam.cy) / cam.fy};
}

/// The board plane seen from the camera.
struct Plane {
  explicit Plane(const SE3& T_c_b) : R(T_c_b.rotation()), n(R.col(2)), t(T_c_b.translation()) {}
  Eigen::Matrix3d R;
  Eigen::Vector3d n, t;

  /// Hit of a ray: board (x, y) and the camera-frame depth z; false when the ray is
  /// parallel to the plane or meets it behind the camera.
  bool hit(const Eigen::Vector2d& ray, Eigen::Vector2d& board_xy, double& z) const {
    const Eigen::Vector3d d(ray.x(), ray.y(), 1.0);
    const double den = n.dot(d);
    if (std::abs(den) < 1e-12) return false;
    z = n.dot(t) / den;
    if (!(z > 1e-6)) return false;
    board_xy = (R.transpose() * (z * d - t)).head<2>();
    return true;
  }
};

/// Rays of a grid of raw pixel positions (x0 + i, y0 + j), cached per thread: undistorting
/// every pixel is the costly part and a view set shares one camera.
const std::vector<Eigen::Vector2d>& rayGrid(const PinholeCamera& cam, int nx, int ny, double x0, double y0) {
  struct Cache {
    std::array<double, 9> key{};
    int nx = 0, ny = 0;
    double x0 = 0, y0 = 0;
    std::vector<Eigen::Vector2d> rays;
  };
  // Two entries: the image renderer (pixel corners) and the depth renderer (pixel centres).
  thread_local std::array<Cache, 2> caches;
  thread_local int next = 0;
  const std::array<double, 9> key{cam.fx, cam.fy, cam.cx, cam.cy, cam.dist[0], cam.dist[1], cam.dist[2], cam.dist[3], cam.dist[4]};
  for (Cache& c : caches)
    if (c.key == key && c.nx == nx && c.ny == ny && c.x0 == x0 && c.y0 == y0 && !c.rays.empty()) return c.rays;
  Cache& cache = caches[next];
  next = 1 - next;
  cache.rays.resize(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) cache.rays[static_cast<size_t>(j) * nx + i] = rayOf(cam, x0 + i, y0 + j);
  cache.key = key;
  cache.nx = nx;
  cache.ny = ny;
  cache.x0 = x0;
  cache.y0 = y0;
  return cache.rays;
}

}  // namespace

cv::Mat renderTarget(const Target& target, const PinholeCamera& camera, const SE3& T_c_board,
                     const RenderOptions& options) {
  camera.validate("renderTarget");
  target.validate();
  const int W = camera.width, H = camera.height, ss = std::max(1, options.supersampling);
  const BoardTexture tex(target);

  // Board coordinates at every pixel corner; sub-samples interpolate them (the mapping is
  // smooth at the scale of one pixel). Corner (i, j) sits at raw pixel (i - 0.5, j - 0.5).
  const int CW = W + 1, CH = H + 1;
  std::vector<Eigen::Vector2d> corner_xy(static_cast<size_t>(CW) * CH);
  std::vector<uint8_t> corner_ok(static_cast<size_t>(CW) * CH, 0);
  const std::vector<Eigen::Vector2d>& rays = rayGrid(camera, CW, CH, -0.5, -0.5);
  const Plane plane(T_c_board);
  for (size_t k = 0; k < rays.size(); ++k) {
    double z = 0;
    corner_ok[k] = plane.hit(rays[k], corner_xy[k], z);
  }

  // Reflectance at the pixel corners: a pixel whose four corners agree is uniform (cells are
  // larger than a pixel) and needs no sub-samples; only edge pixels are supersampled.
  std::vector<float> corner_refl(corner_xy.size(), -2.f);
  for (size_t k = 0; k < corner_xy.size(); ++k)
    if (corner_ok[k]) corner_refl[k] = tex.at(corner_xy[k].x(), corner_xy[k].y());

  cv::Mat img(H, W, CV_32F);
  const float bg = static_cast<float>(options.background);
  const float black = static_cast<float>(options.black), white = static_cast<float>(options.white);
  for (int y = 0; y < H; ++y) {
    float* row = img.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      const size_t k00 = static_cast<size_t>(y) * CW + x, k10 = k00 + 1, k01 = k00 + CW, k11 = k01 + 1;
      if (!(corner_ok[k00] && corner_ok[k10] && corner_ok[k01] && corner_ok[k11])) {
        row[x] = bg;
        continue;
      }
      const float r00 = corner_refl[k00];
      if (r00 == corner_refl[k10] && r00 == corner_refl[k01] && r00 == corner_refl[k11]) {
        row[x] = r00 < 0 ? bg : black + r00 * (white - black);
        continue;
      }
      const Eigen::Vector2d &p00 = corner_xy[k00], &p10 = corner_xy[k10], &p01 = corner_xy[k01], &p11 = corner_xy[k11];
      double sum = 0;
      for (int sy = 0; sy < ss; ++sy) {
        const double b = (sy + 0.5) / ss;
        const Eigen::Vector2d l = (1 - b) * p00 + b * p01, r = (1 - b) * p10 + b * p11;
        for (int sx = 0; sx < ss; ++sx) {
          const double a = (sx + 0.5) / ss;
          const Eigen::Vector2d p = (1 - a) * l + a * r;
          const float refl = tex.at(p.x(), p.y());
          sum += refl < 0 ? bg : black + refl * (white - black);
        }
      }
      row[x] = static_cast<float>(sum / (ss * ss));
    }
  }
  if (options.blur_sigma > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), options.blur_sigma, options.blur_sigma, cv::BORDER_REPLICATE);
  if (options.noise_sigma > 0) {
    std::mt19937 rng(options.seed);
    std::normal_distribution<float> noise(0.f, static_cast<float>(options.noise_sigma));
    for (int y = 0; y < H; ++y) {
      float* row = img.ptr<float>(y);
      for (int x = 0; x < W; ++x) row[x] += noise(rng);
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8U);  // rounds and saturates
  return out;
}

cv::Mat renderPlaneDepth(const PinholeCamera& camera, const SE3& T_c_board, const DepthRenderOptions& options) {
  camera.validate("renderPlaneDepth");
  cv::Mat depth(camera.height, camera.width, CV_32F);
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> noise(0.0, options.noise_sigma > 0 ? options.noise_sigma : 1.0);
  const std::vector<Eigen::Vector2d>& rays = rayGrid(camera, camera.width, camera.height, 0.0, 0.0);
  const Plane plane(T_c_board);
  for (int y = 0; y < camera.height; ++y) {
    float* row = depth.ptr<float>(y);
    for (int x = 0; x < camera.width; ++x) {
      Eigen::Vector2d xy;
      double z = 0;
      if (!plane.hit(rays[static_cast<size_t>(y) * camera.width + x], xy, z)) {
        row[x] = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      double m = options.scale * z + options.offset;
      if (options.noise_sigma > 0) m += noise(rng);
      row[x] = static_cast<float>(m);
    }
  }
  return depth;
}

bool targetInView(const Target& target, const PinholeCamera& camera, const SE3& T_c_board, double border) {
  const cv::Rect2d a = target.printedArea();
  const int n = 16;
  for (int e = 0; e < 4; ++e) {
    for (int i = 0; i <= n; ++i) {
      const double s = static_cast<double>(i) / n;
      double x = 0, y = 0;
      switch (e) {
        case 0: x = a.x + s * a.width, y = a.y; break;
        case 1: x = a.x + a.width, y = a.y + s * a.height; break;
        case 2: x = a.x + s * a.width, y = a.y + a.height; break;
        default: x = a.x, y = a.y + s * a.height; break;
      }
      const Eigen::Vector3d p = T_c_board * Eigen::Vector3d(x, y, 0);
      if (p.z() <= 1e-3) return false;
      // Far outside the field of view the distortion polynomial can fold back: test the
      // ideal projection first.
      const Eigen::Vector2d ideal = camera.projectIdeal(p);
      if (ideal.x() < -0.5 * camera.width || ideal.x() > 1.5 * camera.width || ideal.y() < -0.5 * camera.height ||
          ideal.y() > 1.5 * camera.height)
        return false;
      if (!camera.inImage(camera.distort(ideal), border)) return false;
    }
  }
  return true;
}

std::vector<SE3> makeViewPoses(const Target& target, const PinholeCamera& camera, int count, uint32_t seed,
                               const ViewPoseOptions& o) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const cv::Rect2d pattern = target.patternArea();
  const SE3 T_target_board = target.boardFromTarget().inverse();
  const double deg = M_PI / 180.0;
  std::vector<SE3> poses;
  for (int attempt = 0; static_cast<int>(poses.size()) < count; ++attempt) {
    if (attempt > 2000 * count) throw DataError("makeViewPoses: cannot fit the target in the image; use a smaller target or a wider camera");
    const double fill = o.min_fill + (o.max_fill - o.min_fill) * uni(rng);
    const double distance = std::abs(camera.fx) * pattern.width / (fill * camera.width);  // fx is signed
    // Alternate the tilt's sign and axis so the set constrains the focal length well.
    const int k = static_cast<int>(poses.size());
    const double tilt = (0.3 + 0.7 * uni(rng)) * o.max_tilt_deg * deg * ((k / 2) % 2 ? -1 : 1);
    const double other = (uni(rng) - 0.5) * o.max_tilt_deg * deg;
    const double tilt_x = k % 2 ? tilt : other, tilt_y = k % 2 ? other : tilt;
    const double roll = (2 * uni(rng) - 1) * o.max_roll_deg * deg;
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()))
                                  .toRotationMatrix();
    // The pattern centre goes to a random ideal pixel; views whose target leaves the image are redrawn.
    const double u = camera.width * (0.2 + 0.6 * uni(rng)), v = camera.height * (0.2 + 0.6 * uni(rng));
    const Eigen::Vector3d centre = distance * Eigen::Vector3d((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
    const SE3 T_c_board = SE3(R, centre) * T_target_board;
    if (targetInView(target, camera, T_c_board, o.border_px)) poses.push_back(T_c_board);
  }
  return poses;
}

}  // namespace plslam::calib
