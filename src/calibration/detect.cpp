#include "calibration/detect.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam::calib {

const char* viewStatusName(ViewStatus s) {
  switch (s) {
    case ViewStatus::kAccepted: return "accepted";
    case ViewStatus::kUnreadable: return "unreadable";
    case ViewStatus::kNotFound: return "target not found";
    case ViewStatus::kTooBlurry: return "too blurry";
    case ViewStatus::kTooFewPoints: return "too few corners";
    case ViewStatus::kPoorCoverage: return "poor coverage";
    case ViewStatus::kHighError: return "high reprojection error";
    case ViewStatus::kNoDepth: return "no depth";
  }
  return "?";
}

double sharpness(const cv::Mat& grey, const cv::Rect& roi, double percentile) {
  cv::Mat smooth, lap;
  cv::GaussianBlur(grey, smooth, cv::Size(0, 0), 1.0);
  cv::Laplacian(smooth, lap, CV_32F);
  const cv::Rect area = roi.area() > 0 ? (roi & cv::Rect(0, 0, grey.cols, grey.rows)) : cv::Rect(0, 0, grey.cols, grey.rows);
  const int tile = 32;
  std::vector<double> vars;
  for (int y = 0; y + tile / 2 <= grey.rows; y += tile) {
    for (int x = 0; x + tile / 2 <= grey.cols; x += tile) {
      const cv::Rect t = cv::Rect(x, y, tile, tile) & cv::Rect(0, 0, grey.cols, grey.rows);
      if ((t & area).area() == 0) continue;
      cv::Scalar mean, sd;
      cv::meanStdDev(lap(t), mean, sd);
      vars.push_back(sd[0] * sd[0]);
    }
  }
  if (vars.empty()) return 0;
  const size_t k = std::min(vars.size() - 1, static_cast<size_t>(percentile * vars.size()));
  std::nth_element(vars.begin(), vars.begin() + static_cast<long>(k), vars.end());
  return vars[k];
}

struct TargetDetector::AprilTagState {
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
  ~AprilTagState() {
    if (detector) apriltag_detector_destroy(detector);
    if (family) tag36h11_destroy(family);
  }
};

TargetDetector::TargetDetector(const Target& target, const DetectionOptions& options) : target_(target), options_(options) {
  target_.validate();
  if (target_.kind == TargetKind::kAprilGrid) {
    tags_ = std::make_unique<AprilTagState>();
    tags_->family = tag36h11_create();
    tags_->detector = apriltag_detector_create();
    apriltag_detector_add_family_bits(tags_->detector, tags_->family, std::clamp(options_.max_hamming, 0, 2));
    // Full resolution and edge refinement: calibration wants the most accurate corners.
    tags_->detector->quad_decimate = 1.0f;
    tags_->detector->quad_sigma = 0.0f;
    tags_->detector->refine_edges = true;
    tags_->detector->nthreads = 1;
  }
}

TargetDetector::~TargetDetector() = default;

namespace {

double hullAreaFraction(const std::vector<cv::Point2f>& pts, const cv::Size& size) {
  if (pts.size() < 3) return 0;
  std::vector<cv::Point2f> hull;
  cv::convexHull(pts, hull);
  return cv::contourArea(hull) / (static_cast<double>(size.width) * size.height);
}

float meanAround(const cv::Mat& grey, cv::Point2f c, int r) {
  const cv::Rect box = cv::Rect(cvRound(c.x) - r, cvRound(c.y) - r, 2 * r + 1, 2 * r + 1) & cv::Rect(0, 0, grey.cols, grey.rows);
  return box.area() > 0 ? static_cast<float>(cv::mean(grey(box))[0]) : 0.f;
}

/// OpenCV may start the corner list at any of the board's corners. Puts it in the board's
/// own order (Target::points): x along the rows to the right as printed, y down, and the
/// square between the first four corners black (the top-left square is black). The board
/// frame is right-handed with z away from the camera, so x cross y points into the image.
/// A board whose cols + rows is even is symmetric under a half turn: that ambiguity stays.
void canonicalChessboardOrder(const cv::Mat& grey, int cols, int rows, std::vector<cv::Point2f>& c) {
  auto at = [&](int i, int j) -> cv::Point2f& { return c[static_cast<size_t>(j) * cols + i]; };
  const cv::Point2f dx = at(1, 0) - at(0, 0), dy = at(0, 1) - at(0, 0);
  if (dx.x * dy.y - dx.y * dy.x < 0) {
    for (int j = 0; j < rows; ++j) std::reverse(c.begin() + j * cols, c.begin() + (j + 1) * cols);
  }
  const auto centre = [&](int i, int j) { return 0.25f * (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1)); };
  const float side = static_cast<float>(cv::norm(at(1, 1) - at(0, 0)));
  const int r = std::max(1, static_cast<int>(0.15f * side));
  // The square of the first four corners against its neighbour along x.
  if (meanAround(grey, centre(0, 0), r) > meanAround(grey, centre(1, 0), r)) std::reverse(c.begin(), c.end());
}

std::string gridIds(const Target& t) { return str(t.first_id, "..", t.first_id + t.cols * t.rows - 1); }

/// The image as 8-bit grey (shares the pixels of a grey 8-bit input).
cv::Mat toGrey8(const cv::Mat& image, const std::string& name) {
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 1) {
    grey = image;
  } else {
    throw DataError(str(name, ": expected a grey or BGR image, got ", image.channels(), " channels"));
  }
  if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U);
  return grey;
}

/// Sub-pixel refinement of the classic detector's corners. Window: a third of the smallest
/// square side seen, 2..8 pixels.
void refineChessboardCorners(const cv::Mat& grey, const Target& target, std::vector<cv::Point2f>& corners) {
  double side = 1e9;
  for (int j = 0; j < target.rows; ++j)
    for (int i = 0; i + 1 < target.cols; ++i)
      side = std::min(side, static_cast<double>(cv::norm(corners[j * target.cols + i + 1] - corners[j * target.cols + i])));
  const int win = std::clamp(static_cast<int>(side / 3), 2, 8);
  cv::cornerSubPix(grey, corners, cv::Size(win, win), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
}

/// All inner corners of the chessboard in canonical order, or none.
void detectChessboard(const cv::Mat& grey, const Target& target, const DetectionOptions& options,
                      const std::vector<cv::Point3f>& all, Observation* obs) {
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(target.cols, target.rows);
  // The classic detector with sub-pixel refinement is fast and accurate on sharp views;
  // the sector-based one finds boards the classic one misses (blur, uneven light) but
  // takes seconds on an image without a whole board, so it is optional.
  bool found = cv::findChessboardCorners(grey, pattern, corners, cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
  if (!found && sharpness(grey, cv::Rect(), 0.97) >= options.min_sharpness) {
    // Adaptive thresholding copes with uneven light but can take many seconds on a
    // full-resolution image without a whole board: run it at half resolution.
    cv::Mat half;
    cv::resize(grey, half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    found = cv::findChessboardCorners(half, pattern, corners,
                                      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
    for (cv::Point2f& p : corners) p = 2.f * p + cv::Point2f(0.5f, 0.5f);
  }
  if (found) {
    refineChessboardCorners(grey, target, corners);
  } else if (options.chessboard_sb_fallback) {
    found = cv::findChessboardCornersSB(grey, pattern, corners, cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_ACCURACY);
  }
  if (found && static_cast<int>(corners.size()) == target.pointCount()) {
    canonicalChessboardOrder(grey, target.cols, target.rows, corners);
    for (int i = 0; i < target.pointCount(); ++i) {
      obs->ids.push_back(i);
      obs->image.push_back(corners[i]);
      obs->object.push_back(all[i]);
    }
  }
}

/// The four corners of every grid tag seen once and clear of the image border; returns the tag count.
int detectAprilGrid(const cv::Mat& grey, apriltag_detector_t* detector, const Target& target,
                    const DetectionOptions& options, const std::vector<cv::Point3f>& all, Observation* obs) {
  image_u8_t im{grey.cols, grey.rows, static_cast<int32_t>(grey.step[0]), grey.data};
  zarray_t* dets = apriltag_detector_detect(detector, &im);
  std::map<int, int> count;
  std::map<int, apriltag_detection_t*> by_id;
  for (int i = 0; i < zarray_size(dets); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(dets, i, &d);
    if (d->hamming > options.max_hamming || target.tagPointId(d->id, 0) < 0) continue;
    ++count[d->id];
    by_id[d->id] = d;
  }
  const auto nearBorder = [&](const apriltag_detection_t* d) {
    for (int c = 0; c < 4; ++c)
      if (d->p[c][0] < 3.5 || d->p[c][1] < 3.5 || d->p[c][0] > grey.cols - 2.5 || d->p[c][1] > grey.rows - 2.5)
        return true;
    return false;
  };
  int tags = 0;
  for (const auto& [id, d] : by_id) {
    if (count[id] != 1) continue;  // a tag id seen twice is a false detection somewhere
    if (nearBorder(d)) continue;   // a tag cut by the image border gets a corner on the border
    ++tags;
    for (int c = 0; c < 4; ++c) {
      const int pid = target.tagPointId(id, c);
      obs->ids.push_back(pid);
      // apriltag puts pixel centres at +0.5 (pixel i covers [i, i+1)); OpenCV at integers.
      obs->image.emplace_back(static_cast<float>(d->p[c][0] - 0.5), static_cast<float>(d->p[c][1] - 0.5));
      obs->object.push_back(all[pid]);
    }
  }
  apriltag_detections_destroy(dets);
  return tags;
}

/// The verdict on a view whose detection (out->observation, out->tags) is done.
void judgeView(const cv::Mat& grey, const Target& target, const DetectionOptions& options, ViewResult* out) {
  const Observation& obs = out->observation;
  // Sharpness on the target when found (its bounding box), else on the whole image.
  cv::Rect roi;
  if (!obs.image.empty()) roi = cv::boundingRect(obs.image);
  // Without a target, judge the sharpest few tiles: an image with any crisp edge is not blurred.
  out->sharpness = sharpness(grey, roi, obs.image.empty() ? 0.97 : 0.9);
  out->area_fraction = hullAreaFraction(obs.image, grey.size());
  const bool blurry = out->sharpness < options.min_sharpness;
  const std::string blur_text = str("too blurry (sharpness ", cv::format("%.1f", out->sharpness), " < ",
                                    options.min_sharpness, "): hold the camera and target still, focus, add light");

  if (obs.size() == 0) {
    out->status = blurry ? ViewStatus::kTooBlurry : ViewStatus::kNotFound;
    if (blurry) {
      out->reason = "target not found and image " + blur_text;
    } else if (target.kind == TargetKind::kChessboard) {
      out->reason = str("chessboard ", target.cols, "x", target.rows,
                        " not found: all its inner corners must be visible; keep the whole board in view, flat and well lit");
    } else {
      out->reason = str("no tag36h11 tag with id ", gridIds(target), " found: check the target spec and keep the grid in view");
    }
    return;
  }
  if (blurry) {
    out->status = ViewStatus::kTooBlurry;
    out->reason = blur_text;
    return;
  }
  if (target.kind == TargetKind::kAprilGrid) {
    const int need = std::min(options.min_tags, target.cols * target.rows);
    if (out->tags < need) {
      out->status = ViewStatus::kTooFewPoints;
      out->reason = str("only ", out->tags, " of ", target.cols * target.rows, " tags found (need ", need,
                        "): keep more of the grid in view, avoid glare and steep angles");
      return;
    }
  }
  if (out->area_fraction < options.min_area_fraction) {
    out->status = ViewStatus::kPoorCoverage;
    out->reason = str("target covers ", cv::format("%.1f", 100 * out->area_fraction), " % of the image (need ",
                      100 * options.min_area_fraction, " %): move closer");
    return;
  }
  out->status = ViewStatus::kAccepted;
  out->reason = target.kind == TargetKind::kChessboard ? str(obs.size(), " corners")
                                                       : str(out->tags, " tags, ", obs.size(), " corners");
}

}  // namespace

ViewResult TargetDetector::detect(const cv::Mat& image, const std::string& name) const {
  ViewResult out;
  out.name = name;
  if (image.empty()) {
    out.status = ViewStatus::kUnreadable;
    out.reason = "empty image";
    return out;
  }
  const cv::Mat grey = toGrey8(image, name);
  const std::vector<cv::Point3f> all = target_.points();
  if (target_.kind == TargetKind::kChessboard)
    detectChessboard(grey, target_, options_, all, &out.observation);
  else
    out.tags = detectAprilGrid(grey, tags_->detector, target_, options_, all, &out.observation);
  judgeView(grey, target_, options_, &out);
  return out;
}

}  // namespace plslam::calib
