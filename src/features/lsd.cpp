#include "features/lsd.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kDegToRad = static_cast<float>(kPi / 180);
constexpr float kUndefined = -1024.f;  // angle of a pixel whose gradient is under the threshold

void validate(const LsdParameters& p) {
  auto fail = [](const std::string& m) { throw ConfigError("LSD: " + m); };
  if (!(p.scale > 0 && p.scale <= 1)) fail(str("scale ", p.scale, " must be in (0, 1]"));
  if (!(p.sigma_scale > 0)) fail(str("sigma_scale ", p.sigma_scale, " must be positive"));
  if (!(p.quant >= 0)) fail(str("quant ", p.quant, " must not be negative"));
  if (!(p.angle_tol_deg > 0 && p.angle_tol_deg < 180))
    fail(str("angle_tol_deg ", p.angle_tol_deg, " must be in (0, 180)"));
  if (p.bins < 1) fail(str("bins ", p.bins, " must be positive"));
}

// Gaussian sub-sampling: sigma = sigma_scale / scale, the kernel cut where the Gaussian falls
// under 10^-3 of its peak (radius sigma * sqrt(2 * 3 * ln 10)), as the paper and OpenCV do.
cv::Mat subsample(const cv::Mat& grey, const LsdParameters& p) {
  if (p.scale == 1) return grey;
  const double sigma = p.sigma_scale / p.scale;
  const int radius = static_cast<int>(std::ceil(sigma * std::sqrt(6 * std::log(10.0))));
  cv::Mat blurred, small;
  cv::GaussianBlur(grey, blurred, cv::Size(2 * radius + 1, 2 * radius + 1), sigma);
  cv::resize(blurred, small, cv::Size(), p.scale, p.scale, cv::INTER_LINEAR_EXACT);
  return small;
}

struct Pixel {
  int x, y;
};

// The level-line field: per pixel the gradient norm of its 2 x 2 block and the level-line
// angle (the gradient turned by 90 degrees, radians in [0, 2 pi)), and the seeds: pixels
// above the threshold by decreasing norm bin, raster order within a bin.
struct LevelLines {
  int width = 0, height = 0;
  std::vector<float> angle;
  std::vector<float> norm;
  std::vector<Pixel> seeds;

  size_t at(int x, int y) const { return static_cast<size_t>(y) * width + x; }
};

LevelLines levelLines(const cv::Mat& img, double threshold, int bins) {
  LevelLines f;
  f.width = img.cols;
  f.height = img.rows;
  f.angle.assign(static_cast<size_t>(f.width) * f.height, kUndefined);  // the last row and column stay so
  f.norm.assign(f.angle.size(), 0.f);
  double max_norm = 0;
  for (int y = 0; y + 1 < f.height; ++y) {
    const uchar* row = img.ptr<uchar>(y);
    const uchar* next = img.ptr<uchar>(y + 1);
    for (int x = 0; x + 1 < f.width; ++x) {
      const int diagonal = next[x + 1] - row[x], antidiagonal = row[x + 1] - next[x];
      const int gx = diagonal + antidiagonal, gy = diagonal - antidiagonal;  // twice the gradient
      const double norm = std::sqrt((gx * gx + gy * gy) / 4.0);
      f.norm[f.at(x, y)] = static_cast<float>(norm);
      if (norm <= threshold) continue;
      f.angle[f.at(x, y)] = cv::fastAtan2(static_cast<float>(gx), static_cast<float>(-gy)) * kDegToRad;
      max_norm = std::max(max_norm, norm);
    }
  }
  // Counting sort into the bins, highest first: the strongest edges seed the first regions.
  const double bin_of_norm = max_norm > 0 ? (bins - 1) / max_norm : 0;
  std::vector<int> bin(f.angle.size(), -1);
  std::vector<int> start(static_cast<size_t>(bins) + 1, 0);
  for (size_t i = 0; i < f.angle.size(); ++i) {
    if (f.angle[i] == kUndefined) continue;
    bin[i] = bins - 1 - static_cast<int>(f.norm[i] * bin_of_norm);
    ++start[static_cast<size_t>(bin[i]) + 1];
  }
  for (int b = 0; b < bins; ++b) start[static_cast<size_t>(b) + 1] += start[static_cast<size_t>(b)];
  f.seeds.resize(static_cast<size_t>(start[static_cast<size_t>(bins)]));
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const int b = bin[f.at(x, y)];
      if (b >= 0) f.seeds[static_cast<size_t>(start[static_cast<size_t>(b)]++)] = Pixel{x, y};
    }
  return f;
}

// Within `tolerance` of `theta`, both in [0, 2 pi), going round the circle either way.
bool aligned(float angle, float theta, float tolerance) {
  if (angle == kUndefined) return false;
  float difference = std::abs(theta - angle);
  if (difference > 1.5f * static_cast<float>(kPi)) difference = std::abs(difference - 2 * static_cast<float>(kPi));
  return difference <= tolerance;
}

// Grows a region from `seed` over unused 8-neighbours aligned with the region's angle, the
// angle of the summed unit vectors, updated as each pixel joins. Returns that angle.
float growRegion(const LevelLines& f, Pixel seed, float tolerance, std::vector<uint8_t>* used,
                 std::vector<Pixel>* region) {
  region->assign(1, seed);
  (*used)[f.at(seed.x, seed.y)] = 1;
  float theta = f.angle[f.at(seed.x, seed.y)];
  float sum_cos = std::cos(theta), sum_sin = std::sin(theta);
  for (size_t i = 0; i < region->size(); ++i) {
    const Pixel p = (*region)[i];
    for (int y = std::max(p.y - 1, 0); y <= std::min(p.y + 1, f.height - 1); ++y)
      for (int x = std::max(p.x - 1, 0); x <= std::min(p.x + 1, f.width - 1); ++x) {
        const size_t k = f.at(x, y);
        if ((*used)[k] || !aligned(f.angle[k], theta, tolerance)) continue;
        (*used)[k] = 1;
        region->push_back(Pixel{x, y});
        sum_cos += std::cos(f.angle[k]);
        sum_sin += std::sin(f.angle[k]);
        theta = cv::fastAtan2(sum_sin, sum_cos) * kDegToRad;
      }
  }
  return theta;
}

double angleDifference(double a, double b) {
  double d = a - b;
  while (d <= -kPi) d += 2 * kPi;
  while (d > kPi) d -= 2 * kPi;
  return std::abs(d);
}

// The region's segment: through its gradient-weighted centroid along the axis of least
// inertia, turned to point the way of the region's level-line angle, spanning the region.
// In the sub-sampled image's coordinates.
cv::Vec4d regionSegment(const LevelLines& f, const std::vector<Pixel>& region, double theta_region,
                        double tolerance) {
  double cx = 0, cy = 0, weight = 0;
  for (const Pixel& p : region) {
    const double w = f.norm[f.at(p.x, p.y)];
    cx += p.x * w;
    cy += p.y * w;
    weight += w;
  }
  cx /= weight;
  cy /= weight;
  double ixx = 0, iyy = 0, ixy = 0;
  for (const Pixel& p : region) {
    const double w = f.norm[f.at(p.x, p.y)], dx = p.x - cx, dy = p.y - cy;
    ixx += dy * dy * w;
    iyy += dx * dx * w;
    ixy -= dx * dy * w;
  }
  // The eigenvector of the smaller eigenvalue, from whichever row of the matrix is better conditioned.
  const double lambda = 0.5 * (ixx + iyy - std::sqrt((ixx - iyy) * (ixx - iyy) + 4 * ixy * ixy));
  double theta = std::abs(ixx) > std::abs(iyy) ? std::atan2(lambda - ixx, ixy) : std::atan2(ixy, lambda - iyy);
  if (angleDifference(theta, theta_region) > tolerance) theta += kPi;
  const double ux = std::cos(theta), uy = std::sin(theta);
  double lo = 0, hi = 0;
  for (const Pixel& p : region) {
    const double l = (p.x - cx) * ux + (p.y - cy) * uy;
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  }
  return cv::Vec4d(cx + lo * ux, cy + lo * uy, cx + hi * ux, cy + hi * uy);
}

}  // namespace

std::vector<cv::Vec4f> detectLsdSegments(const cv::Mat& grey, const LsdParameters& p) {
  validate(p);
  if (grey.type() != CV_8UC1) throw DataError(str("LSD: image type ", grey.type(), " is not CV_8UC1"));
  std::vector<cv::Vec4f> segments;
  // A 2 x 2 gradient needs two pixels each way after the sub-sampling.
  if (grey.empty() || cvRound(grey.cols * p.scale) < 2 || cvRound(grey.rows * p.scale) < 2) return segments;
  const double tolerance = p.angle_tol_deg * kPi / 180;
  const double threshold = p.quant / std::sin(tolerance);  // a gradient this weak has an unreliable angle
  const LevelLines f = levelLines(subsample(grey, p), threshold, p.bins);
  // The smallest region that could be meaningful at all, by the paper's count of tests.
  const double log_tests = 2.5 * (std::log10(f.width) + std::log10(f.height)) + std::log10(11.0);
  const size_t min_region = static_cast<size_t>(-log_tests / std::log10(p.angle_tol_deg / 180));
  std::vector<uint8_t> used(f.angle.size(), 0);
  std::vector<Pixel> region;
  for (const Pixel& seed : f.seeds) {
    if (used[f.at(seed.x, seed.y)]) continue;
    const float theta = growRegion(f, seed, static_cast<float>(tolerance), &used, &region);
    if (region.size() < min_region) continue;
    const cv::Vec4d s = regionSegment(f, region, theta, tolerance);
    // A region's pixel k is the 2 x 2 block centred at k + 0.5.
    auto out = [&p](double v) { return static_cast<float>((v + 0.5) / p.scale); };
    segments.emplace_back(out(s[0]), out(s[1]), out(s[2]), out(s[3]));
  }
  return segments;
}

}  // namespace plslam
