// Keeps moving objects out of tracking and the map (PLY-SLAM): before a frame is
// tracked, its keypoints are matched to the previous frame's, the matches are checked
// against the camera's motion (3D residuals from depth) and in a Delaunay graph (edges
// whose 3D length changes), and the evidence is fused with the latest instance masks of
// the segmenter into a dynamic mask. Points and lines on the mask's dynamic pixels, and
// points flagged as moving, are removed from the frame's features.
//
// Segmentation runs every `segment_every` frames: on its own thread in the threaded
// pipeline (tracking uses the newest masks that are ready, however old; only the first frame
// waits for its own), or inline in sequential mode (deterministic).
//
// With `latency_frames` k > 0, segmentation follows a fixed schedule (every segment_every-th
// frame) and the masks of frame n are used from frame n + k on, in both modes: the threaded
// filter waits for them when the worker is behind, and keeps them back when it is ahead. A slow
// segmenter's stale masks can so be reproduced exactly with a fast one (replayed masks).
//
// Late masks (threaded mode, or a latency) older than the frame are carried to it
// (`propagate_masks`, mask_propagation.h).
//
// Thread safety: process() from one thread (the tracking thread).
#pragma once

#include <array>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/map.h"
#include "dynamic/delaunay_motion.h"
#include "dynamic/dynamic_mask.h"
#include "dynamic/free_space_check.h"
#include "dynamic/label_spread.h"
#include "dynamic/mask_propagation.h"
#include "dynamic/motion_check.h"
#include "dynamic/segmenter.h"

namespace plslam {

class OptionTable;
class PointGrid;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindDynamicFilterOptions (frontend/option_keys.cpp). `plslam run --print-config` lists them.
struct DynamicFilterOptions {
  bool enabled = true;
  int segment_every = 3;
  int compare_gap = 3;
  double match_radius_px = 40.0;
  double predicted_search_px = 20.0;
  double predicted_search_support = 2.0;
  double unmatched_search_px = 0.0;
  int match_max_distance = 60;
  float match_ratio = 0.7f;
  double line_masked_fraction = 0.3;
  MotionCheckOptions motion;       ///< geometric check between adjacent frames
  DelaunayMotionOptions delaunay;  ///< Delaunay graph check
  FreeSpaceOptions free_space;     ///< unmatched keypoints against the earlier depth image
  bool spread_labels = true;
  // Off by default: the masks already give a moving object's extent, and on fr3_sitting_static
  // spreading grew moving areas from stray flags onto the static background (docs/RESULTS.md,
  // "Label spreading on frames with masks").
  bool spread_with_masks = false;
  LabelSpreadOptions spread;       ///< how
  DynamicMaskOptions mask;         ///< fusion into the dynamic mask
  // For tests of stale masks (key dynamic.replay_latency_frames).
  int latency_frames = 0;
  bool propagate_masks = true;
  MaskPropagationOptions propagation;  ///< how

  /// Throws ConfigError naming the `dynamic.` key of the first value out of range (values
  /// are refused, never clamped).
  void validate() const;
};

/// Binds the dynamic.* keys of the filter and its checks (frontend/option_keys.cpp).
void bindDynamicFilterOptions(OptionTable* table, DynamicFilterOptions* options);

/// What the filter did with one frame.
struct DynamicFrameResult {
  cv::Mat mask;               ///< CV_8U, 255 = static, 0 = dynamic (empty when the filter is off)
  int points_rejected = 0;    ///< keypoints removed
  int lines_rejected = 0;     ///< segments removed
  bool fresh_segmentation = false;  ///< the masks used are at most segment_every frames old
  int mask_age_frames = -1;         ///< frames between the segmented frame and this one (-1: no masks)
  double segmentation_ms = -1;      ///< time of a segmentation finished for this frame (-1: none)
  double filter_ms = 0;       ///< matching, checks and fusion
  MotionCheckStatus motion_status = MotionCheckStatus::kTooFewCorrespondences;
  int instances_dynamic = 0;  ///< instances judged moving
  int instances = 0;          ///< instances in the segmentation used
  Segmentation segmentation;  ///< the segmentation used, moved to this frame when propagated; empty without one
  bool masks_propagated = false;    ///< `segmentation` was carried here from an older frame
  PropagationStats propagation;     ///< how its instances were carried
  std::vector<InstanceDecision> decisions;  ///< per instance of `segmentation`: dynamic or not, and why
  /// Per input keypoint, what the geometric checks said, after label spreading and before
  /// masks were applied: -1 unjudged, 0 still, 1 moving.
  std::vector<int8_t> point_motion;
  /// Per input keypoint (the indexing of point_motion): 1 if process() kept it in the
  /// features, 0 if it removed it. Empty when the filter is off (all kept).
  std::vector<uint8_t> point_kept;
};

class DynamicFilter {
 public:
  /// `segmenter` may be null (geometry only). `asynchronous`: segment on a worker thread.
  DynamicFilter(PinholeCamera camera, DynamicFilterOptions options, std::unique_ptr<Segmenter> segmenter,
                bool asynchronous);
  ~DynamicFilter();
  DynamicFilter(const DynamicFilter&) = delete;
  DynamicFilter& operator=(const DynamicFilter&) = delete;

  /// Filters `features` (extracted from `frame`) in place. `prior_T_cur_prev` is the
  /// tracker's predicted motion since the previous frame, when it has one (the motion over
  /// compare_gap frames is predicted from it at constant velocity). The checks use the
  /// keypoints only, so `features` may have no lines yet: removeLines() filters them later
  /// with the result (the System overlaps this with the line extraction).
  DynamicFrameResult process(const RgbdFrame& frame, FrameFeatures* features, const std::optional<SE3>& prior_T_cur_prev);
  /// Removes the segments of `features` lying on the dynamic mask of `result` (a result of
  /// process() on the same frame); adds them to result->lines_rejected.
  void removeLines(FrameFeatures* features, DynamicFrameResult* result) const;

 private:
  struct Segmented {  // a segmentation and the frame_count_ of its frame
    PropagationSource source;
    int frame = -1;
  };
  Segmentation latestSegmentation(const RgbdFrame& frame, DynamicFrameResult* result);
  std::optional<Segmented> segmentInline(const RgbdFrame& frame);
  std::optional<Segmented> segmentOnWorker(const RgbdFrame& frame);
  std::optional<Segmented> takeDue(std::deque<Segmented>* segmented) const;
  int dueFrame() const;
  Segmented segmentNow(const RgbdFrame& frame, int frame_number);
  bool carriesMasks() const;
  struct AdjacentMatches {  // keypoint matches with the earlier frame
    std::vector<MotionCorrespondence> corr;
    std::vector<int> keypoint;  // per correspondence, its keypoint in the current frame
    std::vector<int> earlier;   // per correspondence, its keypoint in the earlier frame
  };
  struct CheckedMatches {  // the matches the check used, and its verdict
    AdjacentMatches matches;
    MotionCheckResult motion;
    bool searched_prediction = false;  // matched around the predicted positions
    int judged_late = 0;               // matches found at the estimated motion, judged by it
    int gap = 0;                       // frames between the two (0: no earlier frame yet)
    cv::Mat earlier_depth;             // the earlier frame's depth image (empty: no earlier frame)
  };
  struct EarlierFrame {  // what the check keeps of a frame for the frames to come
    FrameFeatures features;  // keypoints only
    cv::Mat depth_m;         // a copy: callers reuse their buffers
  };
  AdjacentMatches matchAdjacent(const FrameFeatures& before, const FrameFeatures& f, const PointGrid& grid,
                                const std::vector<Eigen::Vector2d>& centres, double radius_px,
                                const std::vector<char>& excluded = {}) const;
  void judgeUnmatched(const FrameFeatures& before, const FrameFeatures& f, const PointGrid& grid,
                      CheckedMatches* checked) const;
  std::vector<Eigen::Vector2d> predictedPositions(const FrameFeatures& before, const SE3& prior) const;
  CheckedMatches bestAdjacentMatches(const FrameFeatures& before, const FrameFeatures& f, const PointGrid& grid,
                                     const std::optional<SE3>& prior) const;
  CheckedMatches checkAdjacent(const FrameFeatures& before, const FrameFeatures& f, const std::optional<SE3>& prior) const;
  std::vector<std::array<cv::Point2f, 3>> labelKeypoints(const FrameFeatures& f, bool have_masks,
                                                         CheckedMatches* checked, DynamicFrameResult* r,
                                                         std::vector<int8_t>* checked_labels) const;
  DynamicMaskResult fuseEvidence(CheckedMatches* checked, const Segmentation& seg,
                                 const std::vector<std::array<cv::Point2f, 3>>& moving_triangles,
                                 DynamicFrameResult* r) const;
  void removeRejected(FrameFeatures* f, const CheckedMatches& checked, const DynamicMaskResult& fused,
                      const std::vector<int8_t>& checked_motion, DynamicFrameResult* r) const;
  void logFrame(const CheckedMatches& checked, const DynamicFrameResult& r, size_t points_left) const;
  CheckedMatches checkAgainstHistory(const RgbdFrame& frame, const FrameFeatures& f,
                                     const std::optional<SE3>& prior_T_cur_prev);
  void flagArrivals(const FrameFeatures& f, const SurfaceGraph& graph, const CheckedMatches& checked,
                    std::vector<int8_t>* point_motion) const;
  void workerLoop();

  PinholeCamera camera_;
  DynamicFilterOptions options_;
  std::unique_ptr<Segmenter> segmenter_;
  bool asynchronous_;
  std::deque<EarlierFrame> previous_;  // the last compare_gap frames, oldest first
  int frame_count_ = 0;
  Segmented latest_;                  // the newest segmentation delivered
  MaskCarrier carrier_;               // carries latest_ to the current frame (propagate_masks)
  std::deque<Segmented> held_back_;   // sequential: segmented, not yet due (latency_frames)

  // Worker: frames to segment (at most one without latency_frames), finished ones in order.
  std::thread worker_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;  // the worker finished a frame
  std::deque<std::pair<RgbdFrame, int>> requests_;  // with the frame_count_ each was taken at
  int last_request_frame_ = -1;  // frame_count_ of the last frame handed to the worker
  std::deque<Segmented> finished_;
  int finished_upto_ = -1;  // frame_count_ of the last frame the worker is done with (failed ones too)
  bool busy_ = false, stop_ = false;
};

/// Removes from `f` the keypoints on dynamic pixels of `mask` or flagged in `point_dynamic`
/// (per keypoint, may be empty). Returns, per keypoint of `f` as it came in, 1 if it was kept.
std::vector<uint8_t> removeDynamicPoints(FrameFeatures* f, const cv::Mat& mask, const std::vector<uint8_t>& point_dynamic);
/// Removes from `f` the segments with more than `line_fraction` of their length on dynamic
/// pixels of `mask`. Returns how many were removed.
int removeDynamicLines(FrameFeatures* f, const cv::Mat& mask, double line_fraction);

}  // namespace plslam
