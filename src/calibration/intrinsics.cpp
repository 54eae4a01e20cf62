#include "calibration/intrinsics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/calib3d.hpp>

#include "camera/camera_file.h"
#include "core/error.h"
#include "core/log.h"

namespace plslam::calib {

namespace {

const Logger kLog("calibration");

SE3 poseFromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Re(r, c) = R.at<double>(r, c);
  return SE3(Re, Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
}

int modelFlags(DistortionModel m) {
  switch (m) {
    case DistortionModel::kNone:
      return cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
    case DistortionModel::kK1: return cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
    case DistortionModel::kK1K2: return cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
    case DistortionModel::kK1K2P1P2: return cv::CALIB_FIX_K3;
    case DistortionModel::kK1K2P1P2K3: return 0;
  }
  return 0;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

struct RunOutput {
  cv::Mat K, dist, std_intr;
  std::vector<cv::Mat> rvecs, tvecs;
  std::vector<double> view_rms;
  double rms = 0;
};

RunOutput runCalibration(const std::vector<const Observation*>& obs, const cv::Size& size, DistortionModel model) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const Observation* o : obs) {
    object.push_back(o->object);
    image.push_back(o->image);
  }
  RunOutput r;
  r.K = cv::Mat::eye(3, 3, CV_64F);
  r.dist = cv::Mat::zeros(1, 5, CV_64F);
  cv::Mat std_extr, per_view;
  const cv::TermCriteria crit(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12);
  cv::calibrateCamera(object, image, size, r.K, r.dist, r.rvecs, r.tvecs, r.std_intr, std_extr, per_view,
                      modelFlags(model), crit);
  // OpenCV's returned RMS is per coordinate pair; recompute it over points for clarity.
  double sq = 0;
  size_t n = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    std::vector<cv::Point2f> proj;
    cv::projectPoints(object[i], r.rvecs[i], r.tvecs[i], r.K, r.dist, proj);
    double s = 0;
    for (size_t k = 0; k < proj.size(); ++k) {
      const cv::Point2f d = proj[k] - image[i][k];
      s += d.x * d.x + d.y * d.y;
    }
    r.view_rms.push_back(std::sqrt(s / std::max<size_t>(1, proj.size())));
    sq += s;
    n += proj.size();
  }
  r.rms = std::sqrt(sq / std::max<size_t>(1, n));
  return r;
}

}  // namespace

DistortionModel parseDistortionModel(const std::string& text) {
  for (DistortionModel m : {DistortionModel::kNone, DistortionModel::kK1, DistortionModel::kK1K2,
                            DistortionModel::kK1K2P1P2, DistortionModel::kK1K2P1P2K3})
    if (text == distortionModelName(m)) return m;
  throw ConfigError("distortion model '" + text + "': expected none, k1, k1k2, k1k2p1p2 or k1k2p1p2k3");
}

const char* distortionModelName(DistortionModel m) {
  switch (m) {
    case DistortionModel::kNone: return "none";
    case DistortionModel::kK1: return "k1";
    case DistortionModel::kK1K2: return "k1k2";
    case DistortionModel::kK1K2P1P2: return "k1k2p1p2";
    case DistortionModel::kK1K2P1P2K3: return "k1k2p1p2k3";
  }
  return "?";
}

namespace {

/// Views in use and the rejection reasons counted, for the "too few views" message.
struct ViewSelection {
  std::vector<size_t> used;
  std::map<std::string, int> rejected;

  DataError tooFew(const IntrinsicsOptions& options, size_t n) const {
    std::string why;
    for (const auto& [reason, count] : rejected) why += str(why.empty() ? "" : ", ", count, " ", reason);
    return DataError(str("calibration needs at least ", options.min_views, " accepted views, got ", used.size(), " of ",
                         n, why.empty() ? "" : " (rejected: " + why + ")",
                         "; take more views of the whole target, sharp and from varied angles"));
  }
  std::vector<const Observation*> observations(const std::vector<ViewResult>& views) const {
    std::vector<const Observation*> obs;
    for (size_t i : used) obs.push_back(&views[i].observation);
    return obs;
  }
};

/// One pass of outlier removal: a view far worse than the rest is a misdetection or a
/// target that moved or bent. Returns whether any view was dropped.
bool dropHighErrorViews(const RunOutput& run, const IntrinsicsOptions& options, std::vector<ViewResult>& views,
                        ViewSelection* sel) {
  const double med = median(run.view_rms);
  const double limit = std::max(options.outlier_factor * med, options.outlier_min_px);
  std::vector<size_t> kept;
  for (size_t k = 0; k < sel->used.size(); ++k) {
    if (run.view_rms[k] > limit) {
      ViewResult& v = views[sel->used[k]];
      v.status = ViewStatus::kHighError;
      v.reason = str("reprojection RMS ", cv::format("%.2f", run.view_rms[k]), " px is far above the median ",
                     cv::format("%.2f", med), " px: a misdetection, or the target moved or is not flat");
      ++sel->rejected[viewStatusName(v.status)];
    } else {
      kept.push_back(sel->used[k]);
    }
  }
  if (kept.size() == sel->used.size()) return false;
  sel->used = kept;
  return true;
}

void setCamera(const RunOutput& run, const cv::Size& image_size, const IntrinsicsOptions& options, PinholeCamera* cam) {
  cam->name = options.camera_name;
  cam->width = image_size.width;
  cam->height = image_size.height;
  cam->fx = run.K.at<double>(0, 0);
  cam->fy = run.K.at<double>(1, 1);
  cam->cx = run.K.at<double>(0, 2);
  cam->cy = run.K.at<double>(1, 2);
  for (int i = 0; i < 5; ++i) cam->dist[i] = run.dist.at<double>(i);
  cam->depth_scale = options.depth_scale;
}

/// Per used view its RMS and board pose; the coverage of the image and the tilted views, for the guidance lines.
void measureViews(const RunOutput& run, const std::vector<size_t>& used, const cv::Size& image_size,
                  IntrinsicsResult* res) {
  const int gx = 8, gy = 6;
  std::vector<uint8_t> cells(gx * gy, 0);
  for (size_t k = 0; k < used.size(); ++k) {
    res->view_rms_px[used[k]] = run.view_rms[k];
    res->T_c_board[used[k]] = poseFromRvecTvec(run.rvecs[k], run.tvecs[k]);
    const Eigen::Vector3d normal = res->T_c_board[used[k]].rotation().col(2);
    if (std::acos(std::min(1.0, std::abs(normal.z()))) > 15.0 * M_PI / 180.0) ++res->tilted_views;
    for (const cv::Point2f& p : res->views[used[k]].observation.image) {
      const int cx = std::clamp(static_cast<int>(p.x * gx / image_size.width), 0, gx - 1);
      const int cy = std::clamp(static_cast<int>(p.y * gy / image_size.height), 0, gy - 1);
      cells[cy * gx + cx] = 1;
    }
  }
  res->coverage = static_cast<double>(std::count(cells.begin(), cells.end(), 1)) / cells.size();
}

void addGuidance(IntrinsicsResult* res) {
  const PinholeCamera& cam = res->camera;
  if (res->coverage < 0.7)
    res->guidance.push_back(str("the target's corners reach only ", cv::format("%.0f", 100 * res->coverage),
                                " % of the image: add views with the target near the image corners and edges, "
                                "where distortion shows"));
  if (res->tilted_views < 3)
    res->guidance.push_back(str("only ", res->tilted_views, " views have the target tilted by more than 15 degrees: "
                                "add views tilted 20-45 degrees left/right and up/down (they fix the focal length)"));
  if (res->views_used < 10)
    res->guidance.push_back(str(res->views_used, " views used: 10-20 varied views give a more reliable calibration"));
  if (res->rms_px > 1.0)
    res->guidance.push_back(str("reprojection RMS ", cv::format("%.2f", res->rms_px),
                                " px is high: check the target size in --target, that it is flat, and the focus"));
  if (res->std_dev[0] > 0.005 * cam.fx || res->std_dev[1] > 0.005 * cam.fy)
    res->guidance.push_back(str("focal length uncertain (fx +- ", cv::format("%.2f", res->std_dev[0]),
                                " px): add tilted views at several distances"));
}

}  // namespace

IntrinsicsResult calibrateIntrinsics(std::vector<ViewResult> views, const cv::Size& image_size,
                                     const IntrinsicsOptions& options) {
  IntrinsicsResult res;
  res.views = std::move(views);
  res.model = options.model;
  const size_t n = res.views.size();
  res.view_rms_px.assign(n, std::numeric_limits<double>::quiet_NaN());
  res.T_c_board.assign(n, SE3());

  ViewSelection sel;
  for (size_t i = 0; i < n; ++i) {
    if (res.views[i].accepted()) {
      sel.used.push_back(i);
    } else {
      ++sel.rejected[viewStatusName(res.views[i].status)];
    }
  }
  if (static_cast<int>(sel.used.size()) < std::max(3, options.min_views)) throw sel.tooFew(options, n);

  RunOutput run = runCalibration(sel.observations(res.views), image_size, options.model);
  if (dropHighErrorViews(run, options, res.views, &sel)) {
    if (static_cast<int>(sel.used.size()) < std::max(3, options.min_views)) throw sel.tooFew(options, n);
    run = runCalibration(sel.observations(res.views), image_size, options.model);
  }

  setCamera(run, image_size, options, &res.camera);
  for (int i = 0; i < 4 && i < run.std_intr.rows; ++i) res.std_dev[i] = run.std_intr.at<double>(i);
  res.rms_px = run.rms;
  res.views_used = static_cast<int>(sel.used.size());
  measureViews(run, sel.used, image_size, &res);
  addGuidance(&res);
  const PinholeCamera& cam = res.camera;
  kLog.info(str("calibrated from ", res.views_used, " views of ", n, ": fx ", cam.fx, " fy ", cam.fy, " cx ", cam.cx,
                " cy ", cam.cy, ", RMS ", res.rms_px, " px"));
  return res;
}

SE3 estimateBoardPose(const Observation& obs, const PinholeCamera& camera, double* rms_px) {
  if (obs.size() < 4) throw DataError(str("board pose needs at least 4 points, got ", obs.size()));
  const cv::Mat K(camera.K());
  const cv::Mat dist = camera.distCoeffs();
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(obs.object, obs.image, K, dist, rvec, tvec, false, cv::SOLVEPNP_IPPE))
    throw DataError("board pose: PnP failed");
  cv::solvePnPRefineLM(obs.object, obs.image, K, dist, rvec, tvec);
  if (rms_px) {
    std::vector<cv::Point2f> proj;
    cv::projectPoints(obs.object, rvec, tvec, K, dist, proj);
    double s = 0;
    for (size_t i = 0; i < proj.size(); ++i) {
      const cv::Point2f d = proj[i] - obs.image[i];
      s += d.x * d.x + d.y * d.y;
    }
    *rms_px = std::sqrt(s / proj.size());
  }
  return poseFromRvecTvec(rvec, tvec);
}

std::string calibrationComment(const IntrinsicsResult& r, const Target& target) {
  return str("plslam calib intrinsics: target ", target.spec(), ", distortion ", distortionModelName(r.model), ", ",
             r.views_used, " of ", r.views.size(), " views used, reprojection RMS ", cv::format("%.4f", r.rms_px),
             " px, std dev fx fy cx cy ", cv::format("%.3f %.3f %.3f %.3f", r.std_dev[0], r.std_dev[1], r.std_dev[2], r.std_dev[3]),
             " px, image coverage ", cv::format("%.0f", 100 * r.coverage), " %");
}

void saveCalibration(const std::string& path, const IntrinsicsResult& result, const Target& target) {
  saveCameraFile(path, result.camera, calibrationComment(result, target));
}

}  // namespace plslam::calib
