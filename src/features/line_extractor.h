// Line segments: LSD (features/lsd.h; OpenCV's when its refinement is asked for), on a
// reduced image for speed, a merge of collinear fragments (LSD over-segments: one physical
// edge comes out as several pieces), clipping to the mask, a length filter and a cap on the
// count; LBD binary descriptors (features/lbd.h: OpenCV's BinaryDescriptor bits, computed
// faster).
//
// Stateless and deterministic. Thread safety: every function may be called concurrently.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/profile.h"

namespace plslam {

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindFeatureOptions (frontend/feature_extraction.cpp). `plslam run --print-config` lists them.
struct LineOptions {
  // FLD runs without its own merge (merge_* below does that). Both detectors give segments
  // with the brighter side on the left, which the LBD descriptor and the merge rely on.
  std::string detector = "lsd";
  double detect_scale = 0.5;
  double lsd_quant = 2.0;
  bool lsd_refine = false;
  int fld_min_length_px = 10;
  double fld_canny_low = 50;
  double fld_canny_high = 50;
  double merge_angle_deg = 3.0;
  double merge_distance_px = 2.0;
  double merge_gap_px = 12.0;
  double min_length_ratio = 0.04;
  int max_lines = 150;
  double lbd_scale = 0.5;

  /// Throws ConfigError when a value is out of range.
  void validate() const;
};

/// A 2D segment. Direction p -> q is LSD's: walking from p to q the darker side is on the
/// right (image axes, y down), so an edge keeps its direction from frame to frame as long
/// as its contrast does (the LBD descriptor depends on the direction).
struct LineSegment2D {
  Eigen::Vector2d p = Eigen::Vector2d::Zero(), q = Eigen::Vector2d::Zero();  ///< endpoints, pixels
  float length = 0;  ///< |q - p|, pixels
  float angle = 0;   ///< atan2(q.y - p.y, q.x - p.x), radians in (-pi, pi]
  int octave = 0;    ///< pyramid level it was described at (0: the image itself)

  /// A segment with length and angle filled in.
  static LineSegment2D fromEndpoints(const Eigen::Vector2d& p, const Eigen::Vector2d& q, int octave = 0);
};

/// How many segments each stage left, for the run statistics.
struct LineStats {
  int detected = 0;     ///< raw detector segments
  int merged = 0;       ///< after merging fragments
  int unmasked = 0;     ///< after dropping (or clipping) what lies on forbidden pixels
  int long_enough = 0;  ///< after the length filter
  int kept = 0;         ///< after the cap (= the number returned)
};

/// Detector (LSD or FLD) + merge + mask + length filter + cap, longest first. `image`: CV_8UC1/3/4.
/// `mask`: empty or CV_8UC1 of the image size, 0 = forbidden: a segment keeps only its
/// longest stretch of allowed pixels (sampled every pixel), dropped when none.
/// Empty or tiny images give no segments. Throws DataError / ConfigError like extractOrb.
/// `times` (optional) gets the kLsd and kLineMerge stages.
std::vector<LineSegment2D> detectLines(const cv::Mat& image, const cv::Mat& mask, const LineOptions& options,
                                       LineStats* stats = nullptr, StageTimes* times = nullptr);

/// Joins collinear fragments, iterating until nothing changes: same direction within
/// merge_angle_deg (the same polarity), the shorter one's endpoints within merge_distance_px
/// of the longer one's line, and a gap of at most merge_gap_px between them along it (overlap
/// counts as no gap). The joined segment lies on the length-weighted mean line and spans the
/// extreme projections of the endpoints. Longest first; deterministic.
std::vector<LineSegment2D> mergeSegments(std::vector<LineSegment2D> segments, const LineOptions& options);

/// Keeps the longest stretch of `segment` on allowed mask pixels; false when none is left.
bool clipSegmentToMask(const cv::Mat& mask, LineSegment2D* segment);

/// LBD descriptors: CV_8U, one 32-byte row per segment in the same order (0 rows for none).
/// `image`: the one the segments were detected on (CV_8UC1/3/4).
cv::Mat describeLines(const cv::Mat& image, const std::vector<LineSegment2D>& lines, const LineOptions& options);

}  // namespace plslam
