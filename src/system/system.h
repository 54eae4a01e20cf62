// The facade of the SLAM pipeline: feed frames, get poses; finish; read the trajectory,
// the map and the run statistics.
//
//   System slam(camera, options);
//   slam.start();
//   for (frame : source) slam.feed(frame);
//   slam.finish();
//   slam.trajectory();  // every tracked frame, final (optimised) poses
//
// Two modes: threaded (tracking on the caller's thread, local mapping on its own, loop
// closure on a third, connected by queues; a loop correction is solved without the map lock
// and holds tracking only while it is applied), and sequential (the same stages, run in a
// fixed order on the caller's thread: deterministic, for tests and reproducible figures).
//
// Thread safety: start/feed/finish from one thread; the accessors after finish(), except where
// one says otherwise (stats(), keyframeCount()). A worker thread's exception stops the pipeline
// and is rethrown by feed() or finish().
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "camera/depth_correction.h"
#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/map.h"
#include "core/option_table.h"
#include "core/profile.h"
#include "core/trajectory.h"
#include "dense/dense_options.h"
#include "dynamic/segmenter.h"
#include "frontend/dynamic_filter.h"
#include "frontend/feature_extraction.h"
#include "frontend/frame_refinement.h"
#include "frontend/tracker.h"
#include "loop/loop_closer.h"
#include "mapping/local_mapper.h"

namespace plslam {

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// system/system_options.cpp (bindOptions and its helpers). `plslam run --print-config` lists them.
struct SystemOptions {
  bool sequential = false;
  bool use_lines = true;
  int mapping_queue = 8;
  int background_nice = 5;
  FeatureOptions features;      ///< ORB and line extraction
  TrackerOptions tracker;       ///< tracking
  LocalMapperOptions mapper;    ///< local mapping
  DynamicFilterOptions dynamic; ///< rejection of moving objects (dynamic.enabled = false: none)
  SegmenterOptions segmenter;   ///< instance segmentation backend (kind none: geometry only)
  DenseOptions dense;           ///< dense clouds per keyframe and the dense products (dense/)
  bool use_loop = true;
  LoopOptions loop;             ///< loop closure
  // Frame refinement (frame_refinement.h): the frame count bounds what a run without new
  // keyframes (a loaded map) holds; finish() refines the rest.
  bool refine_frames = true;
  int refine_after_keyframes = 8;
  int refine_after_frames = 300;
  // The sensor's calibration: session/run_config loads the camera-to-base file into
  // dense.T_base_cam; feed() applies the depth correction.
  std::string camera_to_base;
  DepthCorrection depth_correction;
};

/// Binds every field of `options` that a configuration file may set.
void bindOptions(OptionTable* table, SystemOptions* options);

/// One input frame's outcome, for the trajectory and the statistics.
struct FrameRecord {
  TimeNs t_ns = 0;
  TrackingStatus status = TrackingStatus::kNotInitialized;
  TrackingMethod method = TrackingMethod::kNone;  ///< how the pose was found
  Id reference_keyframe = kNoId;
  SE3 T_ref_c;              ///< pose relative to the reference keyframe (so BA corrections carry over)
  double tracking_ms = 0;   ///< from the frame's arrival to its pose (features included)
  double features_ms = 0;   ///< until the features are ready: extraction and the dynamic check (which overlaps it)
  int points = 0, lines = 0, matched_points = 0, matched_lines = 0;
  int local_points = 0, local_lines = 0;  ///< the local map searched (TrackingResult)
  int dynamic_points_rejected = 0, dynamic_lines_rejected = 0;
  double segmentation_ms = -1;   ///< a segmentation that finished for this frame (-1: none)
  bool fresh_segmentation = false;  ///< masks at most dynamic.segment_every frames old
  int mask_age_frames = -1;
  int keyframes_before = 0;       ///< keyframes made before this frame (when to refine it)
  FrameObservations observations; ///< its inlier matches, until it is refined
  bool refined = false;           ///< T_ref_c was re-estimated against the settled map
  double refinement_ms = 0;       ///< time feed() spent refining earlier frames after this one's pose
  StageTimes stages;              ///< where the tracking time went (core/profile.h)
};

struct RunStats {
  int frames = 0, tracked = 0, keyframes = 0, lost_events = 0, relocalisations = 0;
  int reanchors = 0;  ///< losses ended by a new keyframe at the last pose (TrackerOptions::reanchor_after_s)
  int map_points = 0, map_lines = 0;
  double line_rate_fitting = 0, line_rate_endpoints = 0;
  int line_rate_keyframes = 0;
  std::vector<double> tracking_ms, features_ms, ba_ms;
  std::vector<double> dynamic_points_rejected, segmentation_ms, mask_age_frames;
  int fresh_segmentations = 0;
  int refined_frames = 0;  ///< frames whose pose was re-estimated against the settled map
  std::array<int, kTrackingMethodCount> methods{};  ///< frames per TrackingMethod
  std::vector<double> recovery_frames, recovery_s;  ///< per loss that was recovered: lost frames, seconds to the recovery
  std::vector<double> refinement_ms;  ///< per frame, the refinement of earlier frames feed() did after its pose
  std::array<std::vector<double>, kStageCount> stage_ms;  ///< per stage (core/profile.h), per frame
  bool use_lines = true, sequential = false, use_dynamic = false;
  std::string segmenter = "none";
  bool use_loop = false;
  LoopStats loop;  ///< loop closure: candidates, accepted, refused per LoopStatus, correction times
};

class System {
 public:
  System(PinholeCamera camera, SystemOptions options);
  /// Starts from a loaded map (mapfile/map_file.h): the first frame is relocalised in it.
  /// With options.tracker.localization_only the map is never changed (no keyframes, no
  /// mapping), and the trajectory is in the map's world frame.
  System(PinholeCamera camera, SystemOptions options, Map map);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  void start();
  /// Tracks one frame; `mask` (CV_8U, 0 = forbidden) keeps features off regions such as
  /// moving objects. Frames must come in time order.
  TrackingResult feed(const RgbdFrame& frame, const cv::Mat& mask = cv::Mat());
  /// Waits for the local mapper to process every queued keyframe, then stops it.
  /// A failure of the mapping or loop thread stops the pipeline; feed() and finish() then
  /// throw Error naming the thread and the cause (the frames tracked so far stay readable).
  void finish();
  /// Between two frames (feed()'s thread): track in the map without changing it from the
  /// next frame on (no keyframes; tracker.localization_only), or map again. Keyframes made
  /// before the switch are still mapped (threaded: the mapping queue's, within a few frames).
  /// Loop closure only runs when the System was made mapping (a System made localising has
  /// none, so it maps without it after a switch).
  void setLocalizationOnly(bool on);
  bool localizationOnly() const { return options_.tracker.localization_only; }
  /// Called with each keyframe's id once it is mapped (dense cloud, lines, local BA, and the
  /// loop closer in sequential mode), on the mapping thread: what publishes maps while a run
  /// goes on hooks in here. An exception from it is a mapping-thread failure. Before start().
  void setKeyframeObserver(std::function<void(Id)> observer);

  /// Every tracked frame with its final pose (reference keyframe pose * relative pose).
  Trajectory trajectory() const;
  /// Keyframe poses, in id order.
  Trajectory keyframeTrajectory() const;
  /// Also between feed() calls of a running pipeline, from feed()'s thread: the mapping and
  /// loop threads' figures are copied under their locks, the map's sizes under its mutex.
  RunStats stats() const;
  /// Keyframes in the map now (under the map's mutex): from any thread, also mid-run.
  int keyframeCount() const;
  /// Unsynchronised: read it after finish(), or hold map().mutex() while the pipeline runs.
  const Map& map() const { return map_; }
  /// The loop closer (its candidate log), null with use_loop off.
  const LoopCloser* loopCloser() const;
  const std::vector<FrameRecord>& records() const { return records_; }
  const PinholeCamera& camera() const { return camera_; }
  const SystemOptions& options() const { return options_; }

 private:
  struct Pipeline;
  PinholeCamera camera_;
  SystemOptions options_;
  Map map_;
  std::unique_ptr<Pipeline> pipeline_;
  std::vector<FrameRecord> records_;
  int keyframes_made_ = 0;
  size_t next_to_refine_ = 0;  // records before this one are refined or cannot be
  /// Refines up to `max_frames` of the records tracked at least `after_keyframes` keyframes
  /// or `after_frames` frames ago.
  void refineSettledFrames(int after_keyframes, int after_frames, size_t max_frames);
};

}  // namespace plslam
