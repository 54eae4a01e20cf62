// From an RGB-D frame to the features the tracker uses: ORB keypoints and LSD/LBD line
// segments (on two threads), moved to ideal pixels, keypoints given their depth.
#pragma once

#include <future>
#include <optional>
#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/map.h"
#include "core/option_table.h"
#include "core/profile.h"
#include "core/worker_thread.h"
#include "features/line_extractor.h"
#include "features/orb_extractor.h"

namespace plslam {

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindFeatureOptions (frontend/feature_extraction.cpp). `plslam run --print-config` lists them.
struct FeatureOptions {
  OrbOptions orb;        ///< keypoints
  LineOptions lines;     ///< line segments
  bool use_lines = true; ///< extract line segments at all
  bool parallel = true;
  double min_depth_m = 0.1;
};

void bindFeatureOptions(OptionTable* table, FeatureOptions* options);

/// One frame's extraction in two halves, so that work on the keypoints (the dynamic check)
/// can run while the segments are still being extracted: the constructor starts the lines
/// (on another thread when options.parallel), points() extracts the keypoints on the
/// caller's thread, addLines() waits for the segments and appends them. `frame`, `mask`,
/// `camera` and `options` must outlive the object. The result is the same as extractFeatures.
/// `line_worker` (optional) runs the segments when options.parallel, and before them the FAST
/// corners of the ORB pyramid's coarser levels (the segments take less time than the
/// keypoints and the dynamic check, so the other thread has room for them); without one, a
/// thread is started for the segments alone (what a caller that extracts a frame now and
/// then wants; a caller that extracts every frame of a stream should keep a WorkerThread and
/// hand it in).
class FeatureExtraction {
 public:
  FeatureExtraction(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera, const FeatureOptions& options,
                    WorkerThread* line_worker = nullptr);
  ~FeatureExtraction();  ///< waits for the line thread
  FeatureExtraction(const FeatureExtraction&) = delete;
  FeatureExtraction& operator=(const FeatureExtraction&) = delete;

  /// Keypoints with descriptors and depth; no lines yet. Call once, before addLines().
  FrameFeatures points(StageTimes* times = nullptr);
  /// Appends the segments and their descriptors to `f` (none when lines are off).
  void addLines(FrameFeatures* f, StageTimes* times = nullptr);

 private:
  struct Lines {
    std::vector<LineSegment2D> segments;
    cv::Mat descriptors;
  };
  Lines runLines();

  const RgbdFrame& frame_;
  const cv::Mat& mask_;
  const PinholeCamera& camera_;
  const FeatureOptions& options_;
  cv::Mat grey_;
  std::optional<OrbExtraction> orb_;
  StageTimes orb_times_;     // the pyramid, built by the constructor
  StageTimes coarse_times_;  // written by the coarse levels' job only, read after it finished
  std::future<void> coarse_levels_;
  StageTimes line_times_;    // written by the line job only, read after it finished
  std::future<Lines> lines_;
};

/// `mask` (CV_8U, 0 = forbidden; may be empty) keeps features off those pixels. `times`
/// (optional) gets the extraction stages (ORB, LSD, merge, LBD, undistortion).
FrameFeatures extractFeatures(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera,
                              const FeatureOptions& options, StageTimes* times = nullptr);

}  // namespace plslam
