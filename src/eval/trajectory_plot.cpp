#include "eval/trajectory_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {
const cv::Scalar kBackground(255, 255, 255);
const cv::Scalar kText(30, 30, 30);
const cv::Scalar kGroundTruth(170, 170, 170);
const int kFont = cv::FONT_HERSHEY_SIMPLEX;

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

/// The largest 1, 2 or 5 times a power of ten that is at most `limit`.
double niceLength(double limit) {
  const double p = std::pow(10.0, std::floor(std::log10(limit)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= limit) return m * p;
  return p;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale, int thickness = 1) {
  cv::putText(img, s, at, kFont, scale, kText, thickness, cv::LINE_AA);
}

constexpr int kShift = 4;  // sub-pixel drawing

/// The plot's view: the two axes kept (the ground truth's smallest extent dropped), the
/// bounds of both trajectories, and their mapping to pixels (equal scale on both axes).
struct PlotView {
  int ax = 0, ay = 2, drop = 1;
  Eigen::Vector3d lo, hi;
  cv::Rect area;
  double s = 1, ox = 0, oy = 0;  // pixels per metre, origin

  cv::Point2d px(const Eigen::Vector3d& p) const {
    return cv::Point2d(ox + (p[ax] - lo[ax]) * s, oy + (hi[ay] - p[ay]) * s);  // up is +second axis
  }
  static cv::Point fp(const cv::Point2d& q) { return cv::Point(cvRound(q.x * (1 << kShift)), cvRound(q.y * (1 << kShift))); }
};

// Layout: title band on top, colour bar on the right, the plot in the rest.
constexpr int kTop = 120, kBottom = 60, kLeft = 30, kRight = 150;

PlotView planView(const std::vector<Eigen::Vector3d>& p_gt, const std::vector<Eigen::Vector3d>& p_est,
                  const PlotOptions& options) {
  PlotView v;
  v.lo = p_gt.front(), v.hi = p_gt.front();
  for (const auto* list : {&p_gt, &p_est})
    for (const Eigen::Vector3d& p : *list) {
      v.lo = v.lo.cwiseMin(p);
      v.hi = v.hi.cwiseMax(p);
    }
  // Drop the axis of smallest ground-truth extent; keep the other two in order.
  Eigen::Vector3d gt_lo = p_gt.front(), gt_hi = p_gt.front();
  for (const Eigen::Vector3d& p : p_gt) {
    gt_lo = gt_lo.cwiseMin(p);
    gt_hi = gt_hi.cwiseMax(p);
  }
  (gt_hi - gt_lo).minCoeff(&v.drop);
  v.ax = v.drop == 0 ? 1 : 0, v.ay = v.drop == 2 ? 1 : 2;
  const int W = options.width, H = options.height;
  v.area = cv::Rect(kLeft, kTop, W - kLeft - kRight, H - kTop - kBottom);
  const double span_x = std::max(v.hi[v.ax] - v.lo[v.ax], 1e-9), span_y = std::max(v.hi[v.ay] - v.lo[v.ay], 1e-9);
  v.s = std::min(v.area.width / span_x, v.area.height / span_y);
  v.ox = v.area.x + 0.5 * (v.area.width - v.s * span_x), v.oy = v.area.y + 0.5 * (v.area.height - v.s * span_y);
  return v;
}

/// Colour map lookup: error in [e_min, e_max] -> JET.
struct ErrorColours {
  cv::Mat lut;
  double e_min = 0, e_max = 1;

  explicit ErrorColours(const AteResult& ate) {
    cv::Mat ramp(256, 1, CV_8UC1);
    for (int v = 0; v < 256; ++v) ramp.at<uchar>(v) = static_cast<uchar>(v);
    cv::applyColorMap(ramp, lut, cv::COLORMAP_JET);
    e_min = ate.stats.min, e_max = std::max(ate.stats.max, ate.stats.min + 1e-12);
  }
  cv::Scalar operator()(double e) const {
    const int v = std::clamp(static_cast<int>(std::lround(255.0 * (e - e_min) / (e_max - e_min))), 0, 255);
    const cv::Vec3b c = lut.at<cv::Vec3b>(v);
    return cv::Scalar(c[0], c[1], c[2]);
  }
};

/// Title and legend, in the band above the plot.
void drawTitleAndLegend(cv::Mat& img, const AteResult& ate, const PlotOptions& options, const PlotView& v,
                        const ErrorColours& colour) {
  const char* names = "xyz";
  text(img, str("ATE RMSE ", fmt("%.4f", ate.stats.rmse), " m  (", ate.pairs.size(), " pairs, max ",
                fmt("%.4f", ate.stats.max), " m)"),
       {kLeft, 30}, 0.8, 2);
  if (!options.title.empty()) text(img, options.title, {kLeft, 58}, 0.5);
  const int ly = 80;
  cv::line(img, {kLeft, ly}, {kLeft + 30, ly}, kGroundTruth, 3, cv::LINE_AA);
  text(img, "ground truth", {kLeft + 38, ly + 5}, 0.5);
  cv::line(img, {kLeft + 170, ly}, {kLeft + 200, ly}, colour(colour.e_max), 2, cv::LINE_AA);
  text(img, "aligned estimate, coloured by its ATE error", {kLeft + 208, ly + 5}, 0.5);
  text(img, str("view from above: ", names[v.ax], "-", names[v.ay], " plane (", names[v.drop],
                ", the axis of smallest extent, dropped)"),
       {kLeft, ly + 26}, 0.5);
}

/// Scale bar, bottom left.
void drawScaleBar(cv::Mat& img, const PlotView& v, int H) {
  const char* names = "xyz";
  const double bar_m = niceLength(0.25 * v.area.width / v.s);
  const int bar_px = static_cast<int>(std::lround(bar_m * v.s));
  const int by = H - 25;
  cv::line(img, {kLeft, by}, {kLeft + bar_px, by}, kText, 2);
  cv::line(img, {kLeft, by - 6}, {kLeft, by + 6}, kText, 2);
  cv::line(img, {kLeft + bar_px, by - 6}, {kLeft + bar_px, by + 6}, kText, 2);
  text(img, fmt("%g m", bar_m), {kLeft + bar_px + 10, by + 5}, 0.5);
  text(img, str("axes: ", names[v.ax], " right, ", names[v.ay], " up (metres, ground-truth frame)"),
       {kLeft + bar_px + 100, by + 5}, 0.45);
}

/// Colour bar, right.
void drawColourBar(cv::Mat& img, const PlotView& v, const ErrorColours& colour, int W) {
  const double e_min = colour.e_min, e_max = colour.e_max;
  const int cb_x = W - kRight + 30, cb_w = 22, cb_top = v.area.y + 30, cb_h = std::max(40, v.area.height - 60);
  text(img, "ATE (m)", {cb_x - 10, cb_top - 12}, 0.5);
  for (int yy = 0; yy < cb_h; ++yy) {
    const double e = e_max - (e_max - e_min) * yy / std::max(1, cb_h - 1);
    cv::line(img, {cb_x, cb_top + yy}, {cb_x + cb_w, cb_top + yy}, colour(e), 1);
  }
  cv::rectangle(img, {cb_x, cb_top}, {cb_x + cb_w, cb_top + cb_h}, kText, 1);
  for (int k = 0; k <= 4; ++k) {
    const int yy = cb_top + (cb_h - 1) * k / 4;
    const double e = e_max - (e_max - e_min) * k / 4.0;
    cv::line(img, {cb_x + cb_w, yy}, {cb_x + cb_w + 5, yy}, kText, 1);
    text(img, fmt("%.4f", e), {cb_x + cb_w + 8, yy + 5}, 0.45);
  }
}

}  // namespace

cv::Mat renderTrajectoryPlot(const Trajectory& gt, const Trajectory& est, const AteResult& ate,
                             const PlotOptions& options) {
  if (options.width < 320 || options.height < 240)
    throw ConfigError(str("plot size ", options.width, "x", options.height, " is too small (at least 320x240)"));
  cv::Mat img(options.height, options.width, CV_8UC3, kBackground);
  if (ate.pairs.empty()) return img;

  // What is drawn: the aligned estimate at its associated poses, and the ground truth over
  // the same time span.
  std::vector<Eigen::Vector3d> p_est;
  for (const StampMatch& m : ate.pairs) p_est.push_back(ate.T_gt_est * est.at(m.second).T_w_c.translation());
  const TimeNs t0 = gt.at(ate.pairs.front().first).t_ns, t1 = gt.at(ate.pairs.back().first).t_ns;
  std::vector<Eigen::Vector3d> p_gt;
  for (const StampedPose& p : gt)
    if (p.t_ns >= t0 && p.t_ns <= t1) p_gt.push_back(p.T_w_c.translation());

  const PlotView v = planView(p_gt, p_est, options);
  for (size_t k = 1; k < p_gt.size(); ++k)
    cv::line(img, v.fp(v.px(p_gt[k - 1])), v.fp(v.px(p_gt[k])), kGroundTruth, 3, cv::LINE_AA, kShift);
  const ErrorColours colour(ate);
  for (size_t k = 1; k < p_est.size(); ++k)
    cv::line(img, v.fp(v.px(p_est[k - 1])), v.fp(v.px(p_est[k])), colour(0.5 * (ate.errors[k - 1] + ate.errors[k])), 2,
             cv::LINE_AA, kShift);
  if (p_est.size() == 1) cv::circle(img, v.px(p_est[0]), 3, colour(ate.errors[0]), cv::FILLED);

  drawTitleAndLegend(img, ate, options, v, colour);
  drawScaleBar(img, v, options.height);
  drawColourBar(img, v, colour, options.width);
  return img;
}

void plotTrajectories(const std::string& path, const Trajectory& gt, const Trajectory& est, const AteResult& ate,
                      const PlotOptions& options) {
  const cv::Mat img = renderTrajectoryPlot(gt, est, ate, options);
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of('/');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  std::vector<uchar> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(has_ext ? path.substr(dot) : std::string(".png"), img, bytes);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw IoError(path + ": cannot encode the plot (use a .png file name)");
  writeFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace plslam
