#include "calibration/depth_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/log.h"

namespace plslam::calib {

namespace {

struct Sample {
  double truth, measured;
};

/// Least-squares line measured = a * truth + b.
void fitLine(const std::vector<Sample>& s, const std::vector<uint8_t>& use, double& a, double& b) {
  double n = 0, st = 0, sm = 0, stt = 0, stm = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    if (!use[i]) continue;
    n += 1;
    st += s[i].truth;
    sm += s[i].measured;
    stt += s[i].truth * s[i].truth;
    stm += s[i].truth * s[i].measured;
  }
  const double den = n * stt - st * st;
  if (n < 2 || std::abs(den) < 1e-12 * n * n) {  // one depth only: offset is not separable, fit scale alone
    a = stt > 0 ? stm / stt : 1.0;
    b = 0;
    return;
  }
  a = (n * stm - st * sm) / den;
  b = (sm - a * st) / n;
}

/// The pixels of one view on the (inset) printed target: true depth from the board pose
/// along each pixel's ray, measured depth from the image. Returns how many were added.
size_t addViewSamples(const DepthView& dv, const PinholeCamera& camera, const cv::Rect2d& inner, int stride, int view,
                      std::vector<Sample>* samples, std::vector<int>* view_of) {
  if (dv.depth_m.type() != CV_32F || dv.depth_m.cols != camera.width || dv.depth_m.rows != camera.height)
    throw DataError(str(dv.name, ": depth must be CV_32F metres of ", camera.width, "x", camera.height));
  const Eigen::Matrix3d R = dv.T_c_board.rotation();
  const Eigen::Vector3d n = R.col(2), t = dv.T_c_board.translation();
  const size_t before = samples->size();
  for (int y = 0; y < camera.height; y += stride) {
    for (int x = 0; x < camera.width; x += stride) {
      const float m = dv.depth_m.at<float>(y, x);
      if (!std::isfinite(m) || m <= 0) continue;
      const Eigen::Vector2d ideal = camera.undistort({static_cast<double>(x), static_cast<double>(y)});
      const Eigen::Vector3d d((ideal.x() - camera.cx) / camera.fx, (ideal.y() - camera.cy) / camera.fy, 1.0);
      const double den = n.dot(d);
      if (std::abs(den) < 1e-9) continue;
      const double z = n.dot(t) / den;
      if (!(z > 0)) continue;
      const Eigen::Vector3d p_b = R.transpose() * (z * d - t);
      if (!inner.contains(cv::Point2d(p_b.x(), p_b.y()))) continue;
      samples->push_back({z, m});
      view_of->push_back(view);
    }
  }
  return samples->size() - before;
}

/// Three passes of fit and rejection beyond outlier_sigmas robust sigmas (MAD), then the
/// final fit on the kept samples.
void robustFit(const std::vector<Sample>& samples, const DepthCheckOptions& o, std::vector<uint8_t>* use, double* sa,
               double* sb) {
  for (int pass = 0; pass < 3; ++pass) {
    fitLine(samples, *use, *sa, *sb);
    std::vector<double> abs_res;
    for (size_t i = 0; i < samples.size(); ++i) abs_res.push_back(std::abs(samples[i].measured - *sa * samples[i].truth - *sb));
    std::vector<double> sorted = abs_res;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
    const double sigma = std::max(1e-5, 1.4826 * sorted[sorted.size() / 2]);
    for (size_t i = 0; i < samples.size(); ++i) (*use)[i] = abs_res[i] <= o.outlier_sigmas * sigma;
  }
  fitLine(samples, *use, *sa, *sb);
}

/// RMS, true-depth range and per-view notes of the fit over the kept samples, and guidance.
void summariseFit(const std::vector<DepthView>& views, const std::vector<Sample>& samples,
                  const std::vector<int>& view_of, const std::vector<uint8_t>& use, DepthFit* fit) {
  const double sa = fit->scale, sb = fit->offset;
  double sq = 0;
  fit->min_true_m = std::numeric_limits<double>::infinity();
  fit->max_true_m = 0;
  std::vector<double> view_sum(views.size(), 0.0);
  std::vector<int> view_n(views.size(), 0);
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!use[i]) continue;
    const double r = samples[i].measured - sa * samples[i].truth - sb;
    sq += r * r;
    ++fit->pixels;
    fit->min_true_m = std::min(fit->min_true_m, samples[i].truth);
    fit->max_true_m = std::max(fit->max_true_m, samples[i].truth);
    view_sum[view_of[i]] += samples[i].measured - samples[i].truth;
    ++view_n[view_of[i]];
  }
  fit->rms_m = std::sqrt(sq / std::max(1, fit->pixels));
  for (size_t v = 0; v < views.size(); ++v) {
    if (view_n[v] == 0) continue;
    ++fit->views;
    fit->view_notes.push_back(str(views[v].name, ": ", view_n[v], " pixels, mean measured - true ",
                                  cv::format("%+.4f", view_sum[v] / view_n[v]), " m"));
  }
  if (fit->max_true_m - fit->min_true_m < 0.3)
    fit->guidance.push_back(str("true depths span only ", cv::format("%.2f", fit->min_true_m), "-",
                                cv::format("%.2f", fit->max_true_m), " m: add views nearer and farther (and tilted) so "
                                "scale and offset separate"));
  if (fit->views < 3) fit->guidance.push_back(str(fit->views, " views used: 3 or more at different distances are better"));
}

}  // namespace

DepthFit fitDepthScaleOffset(const std::vector<DepthView>& views, const PinholeCamera& camera, const Target& target,
                             const DepthCheckOptions& o) {
  DepthFit fit;
  const cv::Rect2d a = target.printedArea();
  const cv::Rect2d inner(a.x + o.inset * a.width, a.y + o.inset * a.height, (1 - 2 * o.inset) * a.width,
                         (1 - 2 * o.inset) * a.height);
  std::vector<Sample> samples;
  std::vector<int> view_of;
  const int stride = std::max(1, o.stride);
  for (size_t v = 0; v < views.size(); ++v) {
    const size_t before = samples.size();
    const size_t got = addViewSamples(views[v], camera, inner, stride, static_cast<int>(v), &samples, &view_of);
    if (static_cast<int>(got) < o.min_pixels) {
      samples.resize(before);
      view_of.resize(before);
      fit.view_notes.push_back(str(views[v].name, ": skipped, only ", got, " valid depth pixels on the target (need ",
                                   o.min_pixels, ")"));
    }
  }
  if (samples.empty())
    throw DataError("depth check: no view has enough valid depth on the target; check that the depth images are "
                    "registered to the colour images and that the depth scale is right");

  std::vector<uint8_t> use(samples.size(), 1);
  double sa = 1, sb = 0;
  robustFit(samples, o, &use, &sa, &sb);
  fit.scale = sa;
  fit.offset = sb;
  summariseFit(views, samples, view_of, use, &fit);
  return fit;
}

}  // namespace plslam::calib
