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
constexpr int kPaddedRows = (kRows + 3) / 4 * 4;
constexpr int kStatistics = 8;              // per band: means and deviations of 4 gradient parts
constexpr int kFloats = kBands * kStatistics;
constexpr int kBytes = 32;

// Gaussian weights, computed as the reference implementation does (its integer divisions
// included), then used as floats. Across the region: centre 31, sigma 31. Within the three
// bands a row touches: centre 10, sigma 7.
double gaussian(int i, double centre, double sigma) {
  return std::exp((i - centre) * (i - centre) * (-1 / (2 * sigma * sigma)));
}

struct Weights {
  std::array<float, kRows> global{};
  std::array<float, 3 * kBandWidth> local{};
  Weights() {
    const double centre_local = (kBandWidth * 3 - 1) / 2, sigma_local = (kBandWidth * 2 + 1) / 2;
    for (int i = 0; i < 3 * kBandWidth; ++i) local[i] = static_cast<float>(gaussian(i, centre_local, sigma_local));
    const double centre_global = (kRows - 1) / 2;
    for (int i = 0; i < kRows; ++i) global[i] = static_cast<float>(gaussian(i, centre_global, centre_global));
  }
};

const Weights& weights() {
  static const Weights w;
  return w;
}

// Four floats or ints, one per row of the support region: the rows are independent, so four
// of them advance together (GCC and Clang vector extensions; SSE2 on x86-64).
using Floats4 = float __attribute__((vector_size(16)));
using Ints4 = int __attribute__((vector_size(16)));

Floats4 broadcast(float v) { return Floats4{v, v, v, v}; }

// std::round(x) clamped to [0, max], lane by lane. x is clamped first (NaN and negatives to
// 0), so the conversion stays in range; for 0 <= x, x - trunc(x) is exact in float, and
// comparing it with 0.5 rounds half away from zero as std::round does.
Ints4 roundClamped(Floats4 x, float max) {
  const Floats4 zero = broadcast(0.f), top = broadcast(max);
  x = x > zero ? x : zero;
  x = x < top ? x : top;
  const Ints4 whole = __builtin_convertvector(x, Ints4);
  const Floats4 fraction = x - __builtin_convertvector(whole, Floats4);
  return whole - (fraction >= broadcast(0.5f));  // a true comparison is -1
}

// The positive part of each lane: adding it, or adding the positive part of -v, gives the
// sums of the reference's "if (v > 0) pos += v; else neg -= v" bit for bit (adding a zero
// leaves a sum as it was, and adding -v is subtracting v), without its mispredicted branches.
Floats4 positivePart(Floats4 v) { return v > broadcast(0.f) ? v : broadcast(0.f); }

// Rows h..h+3 of the support region, starting at (x0[i], y0[i]): for each, the sums of the
// positive and negative gradient projections along the line and across it.
std::array<std::array<float, 4>, 4> rowSums(const cv::Mat& dx, const cv::Mat& dy, const float* x0, const float* y0,
                                            float cos_a, float sin_a, int length) {
  const float max_x = static_cast<float>(dx.cols - 1), max_y = static_cast<float>(dx.rows - 1);
  const size_t stride = dx.step1();
  const short* gx_image = dx.ptr<short>();
  const short* gy_image = dy.ptr<short>();
  const Floats4 c = broadcast(cos_a), s = broadcast(sin_a), minus_s = broadcast(-sin_a);
  Floats4 x = {x0[0], x0[1], x0[2], x0[3]}, y = {y0[0], y0[1], y0[2], y0[3]};
  Floats4 pos_l{}, neg_l{}, pos_o{}, neg_o{};
  for (int w = 0; w < length; ++w) {
    const Ints4 u = roundClamped(x, max_x), v = roundClamped(y, max_y);
    Floats4 gx, gy;
    for (int i = 0; i < 4; ++i) {
      const size_t at = static_cast<size_t>(v[i]) * stride + static_cast<size_t>(u[i]);
      gx[i] = gx_image[at];
      gy[i] = gy_image[at];
    }
    const Floats4 along = gx * c + gy * s, across = gx * minus_s + gy * c;
    pos_l += positivePart(along);
    neg_l += positivePart(-along);
    pos_o += positivePart(across);
    neg_o += positivePart(-across);
    x += c;
    y += s;
  }
  std::array<std::array<float, 4>, 4> rows;
  for (int i = 0; i < 4; ++i) rows[i] = {pos_l[i], neg_l[i], pos_o[i], neg_o[i]};
  return rows;
}

// The four gradient sums of one band, and of their squares: along the line (L) and across
// it (O), positive and negative parts apart.
struct BandSums {
  std::array<float, 4> sum{}, sum2{};
};

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
  // Where each row starts (one more than the region has, so that rows go by fours), stepped
  // from the first as the reference steps them.
  std::array<float, kPaddedRows> x0{}, y0{};
  x0[0] = -cos_a * half_length + sin_a * half_height + mid_x;
  y0[0] = -sin_a * half_length - cos_a * half_height + mid_y;
  for (int h = 1; h < kPaddedRows; ++h) x0[h] = x0[h - 1] - sin_a, y0[h] = y0[h - 1] + cos_a;
  std::array<std::array<float, 4>, kPaddedRows> rows;
  for (int h = 0; h < kPaddedRows; h += 4) {
    const auto four = rowSums(dx, dy, &x0[h], &y0[h], cos_a, sin_a, length);
    std::copy(four.begin(), four.end(), rows.begin() + h);
  }
  for (int h = 0; h < kRows; ++h) {
    std::array<float, 4> row = rows[h];
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
  // The samples are clamped to the image: an empty one has no pixel to clamp them to.
  if (image.empty()) throw Error("describeLbd: segments on an empty image");
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
