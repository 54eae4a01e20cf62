#include "features/lbd.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace plslam {

namespace {

constexpr int kBands = 9;
constexpr int kBandWidth = 7;
constexpr int kRows = kBands * kBandWidth;  // height of the line support region
constexpr int kStatistics = 8;              // per band: means and deviations of 4 gradient parts
constexpr int kFloats = kBands * kStatistics;
constexpr int kBytes = 32;

// Gaussian weights, computed as the reference implementation does (its integer divisions
// included), then used as floats. Across the region: centre 31, sigma 31. Within the three
// bands a row touches: centre 10, sigma 7.
struct Weights {
  std::array<float, kRows> global{};
  std::array<float, 3 * kBandWidth> local{};
  Weights() {
    const double centre_local = (kBandWidth * 3 - 1) / 2, sigma_local = (kBandWidth * 2 + 1) / 2;
    for (int i = 0; i < 3 * kBandWidth; ++i)
      local[i] = static_cast<float>(std::exp((i - centre_local) * (i - centre_local) * (-1 / (2 * sigma_local * sigma_local))));
    const double centre_global = (kRows - 1) / 2, sigma_global = centre_global;
    for (int i = 0; i < kRows; ++i)
      global[i] = static_cast<float>(
          std::exp((i - centre_global) * (i - centre_global) * (-1 / (2 * sigma_global * sigma_global))));
  }
};

const Weights& weights() {
  static const Weights w;
  return w;
}

// std::round(x) clamped to [0, max] for the sample coordinates, without the library call.
// Negative values all clamp to 0; for x >= 0, adding 0.5 in double is exact, so truncating
// rounds half away from zero exactly as std::round does.
inline int roundClamped(float x, int max) {
  if (!(x > 0)) return 0;
  if (x >= static_cast<float>(max)) return max;
  return static_cast<int>(static_cast<double>(x) + 0.5);
}

// The four gradient sums of one band, and of their squares: along the line (L) and across
// it (O), positive and negative parts apart.
struct BandSums {
  std::array<float, 4> sum{}, sum2{};
};

// One row of the support region: the four sums of the gradient projections along it.
std::array<float, 4> rowSums(const cv::Mat& dx, const cv::Mat& dy, float x, float y, float cos_a, float sin_a,
                             int length) {
  const int max_x = dx.cols - 1, max_y = dx.rows - 1;
  float pos_l = 0, neg_l = 0, pos_o = 0, neg_o = 0;
  for (int w = 0; w < length; ++w) {
    const int u = roundClamped(x, max_x), v = roundClamped(y, max_y);
    const float gx = dx.ptr<short>(v)[u], gy = dy.ptr<short>(v)[u];
    const float along = gx * cos_a + gy * sin_a;
    const float across = gx * -sin_a + gy * cos_a;
    // Without branches (the signs are random, and mispredicted branches cost more than the
    // rest of the loop). Adding a zero leaves a sum as it was, and adding -v is subtracting v,
    // so the sums are those of the reference's if/else, bit for bit.
    pos_l += std::max(along, 0.f);
    neg_l += std::max(-along, 0.f);
    pos_o += std::max(across, 0.f);
    neg_o += std::max(-across, 0.f);
    x += cos_a;
    y += sin_a;
  }
  return {pos_l, neg_l, pos_o, neg_o};
}

void addRow(const std::array<float, 4>& row, float weight, BandSums* band) {
  for (int k = 0; k < 4; ++k) {
    band->sum[k] += weight * row[k];
    band->sum2[k] += weight * weight * (row[k] * row[k]);
  }
}

// The 72 statistics of one segment, before normalisation.
std::array<float, kFloats> bandStatistics(const cv::Mat& dx, const cv::Mat& dy, const LbdSegment& s) {
  const Weights& wt = weights();
  std::array<BandSums, kBands> bands{};
  const int length = s.samples;
  const int half_length = (length - 1) / 2, half_height = (kRows - 1) / 2;
  const float mid_x = static_cast<float>(0.5 * (s.start_x + s.end_x));
  const float mid_y = static_cast<float>(0.5 * (s.start_y + s.end_y));
  const float cos_a = static_cast<float>(std::cos(s.angle)), sin_a = static_cast<float>(std::sin(s.angle));
  float x0 = -cos_a * half_length + sin_a * half_height + mid_x;
  float y0 = -sin_a * half_length - cos_a * half_height + mid_y;
  for (int h = 0; h < kRows; ++h) {
    std::array<float, 4> row = rowSums(dx, dy, x0, y0, cos_a, sin_a, length);
    x0 -= sin_a;
    y0 += cos_a;
    for (float& r : row) r *= wt.global[h];
    // A row counts for its own band and, less, for the bands on either side.
    const int band = h / kBandWidth, in_band = h % kBandWidth;
    addRow(row, wt.local[in_band + kBandWidth], &bands[band]);
    if (band > 0) addRow(row, wt.local[in_band + 2 * kBandWidth], &bands[band - 1]);
    if (band + 1 < kBands) addRow(row, wt.local[in_band], &bands[band + 1]);
  }
  std::array<float, kFloats> d{};
  for (int b = 0; b < kBands; ++b) {
    // The outer bands collect rows from two bands, the others from three.
    const float inv_n = static_cast<float>(1.0 / (kBandWidth * ((b == 0 || b == kBands - 1) ? 2.0 : 3.0)));
    for (int k = 0; k < 4; ++k) {
      const float mean = bands[b].sum[k] * inv_n;
      d[b * kStatistics + k] = mean;
      d[b * kStatistics + 4 + k] = std::sqrt(bands[b].sum2[k] * inv_n - mean * mean);
    }
  }
  return d;
}

// Means and deviations normalised apart, each value capped at 0.4 (against non-linear
// lighting changes), then the whole normalised again.
void normalise(std::array<float, kFloats>* d) {
  float means = 0, deviations = 0;
  for (int b = 0; b < kBands; ++b)
    for (int k = 0; k < 4; ++k) {
      means += (*d)[b * kStatistics + k] * (*d)[b * kStatistics + k];
      deviations += (*d)[b * kStatistics + 4 + k] * (*d)[b * kStatistics + 4 + k];
    }
  means = 1 / std::sqrt(means);
  deviations = 1 / std::sqrt(deviations);
  for (int b = 0; b < kBands; ++b)
    for (int k = 0; k < 4; ++k) {
      (*d)[b * kStatistics + k] *= means;
      (*d)[b * kStatistics + 4 + k] *= deviations;
    }
  float total = 0;
  for (float& v : *d) {
    if (v > 0.4) v = 0.4f;
    total += v * v;
  }
  total = 1 / std::sqrt(total);
  for (float& v : *d) v *= total;
}

// Each byte compares the statistics of two bands: bit k set when statistic k of the first
// is the larger. 36 pairs of 9 bands, 32 bytes: the four pairs joining an outer band at one
// end (0 or 1) to one at the other (7 or 8) are left out, the rest in lexicographic order.
void toBinary(const std::array<float, kFloats>& d, uchar* out) {
  int byte = 0;
  for (int a = 0; a < kBands; ++a)
    for (int b = a + 1; b < kBands; ++b) {
      if (a <= 1 && b >= kBands - 2) continue;
      uchar bits = 0;
      for (int k = 0; k < kStatistics; ++k)
        if (d[a * kStatistics + k] > d[b * kStatistics + k]) bits |= static_cast<uchar>(1 << k);
      out[byte++] = bits;
    }
}

}  // namespace

cv::Mat describeLbd(const cv::Mat& image, const std::vector<LbdSegment>& segments) {
  if (image.type() != CV_8UC1) throw Error("describeLbd: the image must be 8-bit grey");
  cv::Mat out(static_cast<int>(segments.size()), kBytes, CV_8U);
  if (segments.empty()) return out;
  cv::Mat smooth, dx, dy;
  cv::GaussianBlur(image, smooth, cv::Size(5, 5), 1);
  cv::Sobel(smooth, dx, CV_16S, 1, 0, 3);
  cv::Sobel(smooth, dy, CV_16S, 0, 1, 3);
  for (size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].samples < 1) throw Error("describeLbd: a segment needs at least one sample");
    std::array<float, kFloats> d = bandStatistics(dx, dy, segments[i]);
    normalise(&d);
    toBinary(d, out.ptr<uchar>(static_cast<int>(i)));
  }
  return out;
}

}  // namespace plslam
