// Target detection in one image with a verdict per view: a chessboard through OpenCV's
// findChessboardCorners + cornerSubPix (optionally findChessboardCornersSB), an AprilTag grid through the
// apriltag library (tag36h11, full resolution, edge-refined corners). Each view is
// accepted or rejected with a reason and a line of guidance for the user.
//
// Thread safety: a TargetDetector must not be used by two threads at once (the apriltag
// detector keeps state); use one per thread.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calibration/target.h"

namespace plslam::calib {

enum class ViewStatus {
  kAccepted,      ///< used for calibration
  kUnreadable,    ///< the image file could not be read
  kNotFound,      ///< no target (chessboard: not all inner corners visible)
  kTooBlurry,     ///< sharpness below DetectionOptions::min_sharpness
  kTooFewPoints,  ///< aprilgrid: fewer than DetectionOptions::min_tags tags
  kPoorCoverage,  ///< the target covers too small a part of the image
  kHighError,     ///< set by the calibration: reprojection error far above the other views'
  kNoDepth,       ///< depth check: no usable depth on the target
};
const char* viewStatusName(ViewStatus s);

/// Detected points of one view: ids index Target::points().
struct Observation {
  std::vector<int> ids;
  std::vector<cv::Point2f> image;   ///< raw (distorted) pixels
  std::vector<cv::Point3f> object;  ///< board-frame coordinates, metres
  size_t size() const { return ids.size(); }
};

struct DetectionOptions {
  double min_sharpness = 25.0;     ///< reject views whose sharpness() is below this
  int min_tags = 4;                ///< aprilgrid: fewest tags for a usable view
  double min_area_fraction = 0.04; ///< the points' convex hull must cover this fraction of the image
  int max_hamming = 1;             ///< aprilgrid: most corrected bit errors accepted per tag
  bool chessboard_sb_fallback = false;  ///< chessboard: try findChessboardCornersSB when the classic detector fails (slow)
};

struct ViewResult {
  std::string name;                          ///< image name, for messages
  ViewStatus status = ViewStatus::kNotFound;
  std::string reason;                        ///< one line: why, and what to do about it
  double sharpness = 0;                      ///< see sharpness()
  double area_fraction = 0;                  ///< convex hull of the points / image area
  int tags = 0;                              ///< aprilgrid: tags found
  Observation observation;                   ///< empty unless points were found
  bool accepted() const { return status == ViewStatus::kAccepted; }
};

/// Variance of the Laplacian of the lightly smoothed (Gaussian sigma 1) image, taken in
/// 32x32 tiles, the `percentile` of the tiles that overlap `roi` (whole image when empty):
/// high on the target's edges when sharp, low when blurred, barely moved by sensor noise.
/// Views use 0.9 over the found target, 0.97 over the whole image when nothing was found.
double sharpness(const cv::Mat& grey, const cv::Rect& roi = cv::Rect(), double percentile = 0.9);

class TargetDetector {
 public:
  explicit TargetDetector(const Target& target, const DetectionOptions& options = {});
  ~TargetDetector();
  TargetDetector(const TargetDetector&) = delete;
  TargetDetector& operator=(const TargetDetector&) = delete;

  /// Detects the target in a grey or BGR image and gives the verdict.
  ViewResult detect(const cv::Mat& image, const std::string& name = "") const;
  const Target& target() const { return target_; }
  const DetectionOptions& options() const { return options_; }

 private:
  struct AprilTagState;
  Target target_;
  DetectionOptions options_;
  std::unique_ptr<AprilTagState> tags_;
};

}  // namespace plslam::calib
