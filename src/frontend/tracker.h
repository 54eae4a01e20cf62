// Frame-by-frame camera tracking against the local map (points and lines).
//
// Per frame: features are given (extracted by the caller with the dynamic mask); the
// pose is predicted with a constant-velocity model, map points and lines of the local
// keyframes are projected and matched in a wide window, the pose is optimised (points
// with depth and lines, robust), then matched again in a narrow window and re-optimised.
// When that leaves too few inliers (fast motion breaks the constant-velocity model, blur
// removes corners) two fallbacks run before the frame is declared lost, as in ORB-SLAM2:
//  1. the reference keyframe: its landmarks matched to the frame through the vocabulary
//     (points and lines, place/vocabulary_matching.h), a pose from PnP RANSAC on the
//     points (or from the prediction when lines must carry the frame), then the local map;
//  2. the motion-model prediction searched in a wider window.
// A lost frame is relocalised by place recognition over the whole map: the keyframes
// whose bags of words look most like the frame (place/keyframe_places.h), each matched
// through the vocabulary, PnP RANSAC, refinement with points and lines, and verification
// by projecting the local map around it. Without a vocabulary the same steps use brute-force
// matching against the most recent keyframes (every keyframe of a loaded map).
// When relocalisation has failed for `reanchor_after_s` (the camera went on to places the
// map never saw, or people covered the view the map was made of), tracking starts again
// from a new keyframe made from the frame's depth at the last tracked pose, in the same
// map: the motion during the loss is lost (the trajectory jumps by it) but the camera is
// not; a later loop closure can pull the two pieces together (loop_closer.cpp weakens the
// pose-graph edge between keyframes that share no landmark).
//
// Thread safety: one Tracker per pipeline, called from one thread; it locks the map's
// mutex while it reads landmarks. applyMapCorrection is called by the loop closer's thread
// while the system holds its tracking mutex, so never during track().
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/id_set.h"
#include "core/map.h"
#include "core/profile.h"
#include "optim/pose_optimizer.h"
#include "place/keyframe_places.h"

namespace plslam {

class OptionTable;

enum class TrackingStatus {
  kInitialized,    ///< first usable frame: the map was created from its depth
  kReanchored,     ///< lost too long to relocalise: a new keyframe at the last tracked pose
  kOk,             ///< tracked
  kRelocalized,    ///< tracked again after being lost
  kNotInitialized, ///< no map yet and this frame cannot start one (reason says why)
  kFewMatches,     ///< too few matches or inliers: lost
  kNoFeatures,     ///< no (or too few) features in the image: lost
};
const char* toString(TrackingStatus status);

/// How a tracked frame got its pose.
enum class TrackingMethod {
  kNone,               ///< not tracked
  kInitialisation,     ///< the first keyframe
  kMotionModel,        ///< constant-velocity prediction, projection search
  kReferenceKeyframe,  ///< fallback 1: vocabulary matches with the reference keyframe
  kWideWindow,         ///< fallback 2: the prediction searched in a wider window
  kRelocalisation,     ///< place recognition after a loss, or fallback 3 before one
  kReanchor,           ///< a new keyframe from the frame's depth at the last tracked pose, after a long loss
};
constexpr int kTrackingMethodCount = 7;
const char* toString(TrackingMethod method);
inline bool isTracked(TrackingStatus s) {
  return s == TrackingStatus::kInitialized || s == TrackingStatus::kOk || s == TrackingStatus::kRelocalized ||
         s == TrackingStatus::kReanchored;
}

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindTrackerOptions (frontend/option_keys.cpp). `plslam run --print-config` lists them.
struct TrackerOptions {
  int min_init_points = 50;
  double max_depth_m = 6.0;
  int min_inliers = 20;
  double wide_radius_px = 15.0;
  double narrow_radius_px = 5.0;
  int max_descriptor_distance = 75;
  float ratio = 0.85f;
  int max_line_descriptor_distance = 80;
  double line_angle_deg = 8.0;
  double line_distance_px = 8.0;
  int local_keyframes = 12;
  int covisible_min_shared = 15;
  double near_plane_m = 0.1;
  int keyframe_max_frames = 20;
  int keyframe_min_frames = 2;
  double keyframe_inlier_ratio = 0.75;
  int keyframe_min_inliers = 120;
  int keyframe_min_support = 40;
  double keyframe_max_translation_m = 0.15;
  double keyframe_max_rotation_deg = 12.0;
  bool use_lines = true;             ///< use line features
  // Hand-held cameras stay under about 2 m/s, a TurtleBot3 under 0.26 m/s.
  double max_speed_m_s = 4.0;
  bool reference_fallback = true;
  double wide_fallback_factor = 3.0;
  bool relocalisation_fallback = true;  ///< last fallback: place recognition on this frame, before "lost"
  int min_vocabulary_matches = 15;
  int min_pnp_points = 12;
  int pnp_iterations = 200;
  double pnp_error_px = 4.0;
  int relocalisation_min_inliers = 40;
  int relocalisation_recent_keyframes = 8;
  PlaceQueryOptions relocalisation;  ///< with a vocabulary: the keyframes relocalisation tries, over the whole map
  // Never used in localisation, nor before a loaded map was first relocalised in.
  double reanchor_after_s = 1.0;
  /// Track against the map without changing it (a loaded map): no keyframes, no landmark
  /// visible/found counts; relocalisation searches every keyframe.
  bool localization_only = false;
  PoseOptimizerOptions optimizer = trackingPoseOptions();  ///< pose-only optimisation

  /// Throws ConfigError naming the first option out of its range (the tracker checks on construction).
  void validate() const;

  /// Depth weighted as in every SLAM solver (kSolverDepthSigmaCoeff).
  static PoseOptimizerOptions trackingPoseOptions() {
    PoseOptimizerOptions o;
    o.model.depth_sigma_coeff = kSolverDepthSigmaCoeff;
    return o;
  }
};

/// Binds the tracker.* keys (frontend/option_keys.cpp).
void bindTrackerOptions(OptionTable* table, TrackerOptions* options);

/// What track() did with one frame.
struct TrackingResult {
  TrackingStatus status = TrackingStatus::kNotInitialized;
  TrackingMethod method = TrackingMethod::kNone;
  std::string reason;         ///< why, when not tracked (or why the motion model failed before a fallback)
  SE3 T_w_c;                  ///< valid when tracked
  bool new_keyframe = false;  ///< a keyframe was made from this frame (id in keyframe_id)
  Id keyframe_id = kNoId;
  Id reference_keyframe = kNoId;  ///< the keyframe the pose is kept relative to
  int matched_points = 0, matched_lines = 0;
  int inliers = 0;
  /// The local map the frame was searched in (landmarks of the local keyframes): the
  /// search's work, whatever the machine's speed. 0 when it was not searched.
  int local_points = 0, local_lines = 0;
  /// When tracked (not on initialisation): the landmark each keypoint / segment was an
  /// inlier match of (kNoId: none), for refining the pose later (frame_refinement.h).
  std::vector<Id> point_matches, line_matches;
  StageTimes times;  ///< kSearch, kPoseOptimisation and kKeyframe of this frame
};

class Tracker {
 public:
  /// When `map` already has keyframes (a loaded map), the first frame is relocalised in it,
  /// searching all its keyframes; otherwise the first usable frame initialises the map.
  /// `vocabulary` (may be null) drives the reference-keyframe fallback and relocalisation.
  Tracker(Map* map, PinholeCamera camera, TrackerOptions options,
          std::shared_ptr<const VocabularySet> vocabulary = nullptr);

  /// Tracks one frame. `features` are in the frame's ideal pixels with depth filled in.
  /// On a new keyframe the keyframe is added to the map (with its matched landmarks)
  /// and its id returned in the result; making its new landmarks is the mapper's job.
  TrackingResult track(TimeNs t_ns, const FrameFeatures& features);

  /// The motion-model prediction of the next frame's motion, T_cur_prev (none when lost
  /// or without two tracked frames yet).
  std::optional<SE3> predictedMotion() const {
    if (!have_velocity_ || lost_) return std::nullopt;
    return T_prev_last_.inverse();
  }
  int lostEvents() const { return lost_events_; }
  int relocalisations() const { return relocalisations_; }
  int reanchors() const { return reanchors_; }
  /// After a loop correction moved the keyframes (T_new_old per keyframe id): the last pose
  /// follows its reference keyframe; the motion model (a relative motion) is kept.
  void applyMapCorrection(const std::map<Id, SE3>& T_new_old) {
    const auto it = T_new_old.find(reference_kf_);
    if (it != T_new_old.end()) T_w_last_ = it->second * T_w_last_;
  }
  const TrackerOptions& options() const { return options_; }
  /// Switches TrackerOptions::localization_only between two frames (a session asked to stop
  /// or resume mapping): from the next frame, no keyframes and no landmark counts, or again.
  void setLocalizationOnly(bool on) { options_.localization_only = on; }

 private:
  /// The landmarks of the local keyframes, in first-seen order (caller holds the map lock).
  struct LocalMap {
    std::vector<Id> point_ids, line_ids;
  };
  struct Matches {
    std::vector<Id> point_ids;  // per keypoint
    std::vector<Id> line_ids;   // per line
    // Landmarks the narrow search predicted inside the image: counted as visible once the
    // frame is tracked (a failed attempt counts nothing).
    std::vector<Id> visible_points, visible_lines;
  };
  /// A pose attempt's outcome.
  struct Attempt {
    bool ok = false;
    SE3 T_w_c;
    int inliers = 0;
    std::string reason;
  };
  TrackingResult initialise(TimeNs t_ns, const FrameFeatures& f);
  /// Lost for reanchor_after_s, relocalisation failed again, and the frame can start a map.
  bool shouldReanchor(TimeNs t_ns, const FrameFeatures& f) const;
  TrackingResult reanchor(TimeNs t_ns, const FrameFeatures& f);
  /// A keyframe made from the frame's depth alone at `T_w_c` (initialisation, re-anchoring).
  TrackingResult startFromDepth(TimeNs t_ns, const FrameFeatures& f, const SE3& T_w_c);
  /// Keypoints whose depth can make a map point.
  int pointsWithDepth(const FrameFeatures& f) const;
  /// track() once the map exists: motion model or relocalisation, then the keyframe decision.
  TrackingResult trackInitialised(TimeNs t_ns, const FrameFeatures& f);
  /// The motion model, then the fallbacks, `dt_s` after the last tracked frame; sets
  /// r->method, r->inliers and r->reason.
  Attempt trackFromLastPose(double dt_s, const FrameFeatures& f, Matches* m, TrackingResult* r);
  /// Projection search of `local` around `T_w_c` in `radius`, then refineWithLocalMap.
  Attempt trackWithPrediction(const LocalMap& local, const SE3& T_w_c, double radius, const FrameFeatures& f, Matches* m);
  /// Fallback 1: the reference keyframe's landmarks matched through the vocabulary.
  Attempt trackReferenceKeyframe(const LocalMap& local, const SE3& predicted, const FrameFeatures& f, Matches* m);
  /// Optimise with the matches in `m`, search `local` in the narrow window, optimise again.
  Attempt refineWithLocalMap(const LocalMap& local, const SE3& T_w_c, const FrameFeatures& f, Matches* m, int min_inliers);
  /// Frame features matched with keyframe `kf`'s landmarks (caller holds the map lock):
  /// through the vocabulary when there is one, else by brute force.
  Matches matchKeyframe(Id kf, const FrameFeatures& f);
  /// PnP RANSAC on the point matches; keeps only its inlier points in `m`. False with too few.
  bool poseByPnP(const FrameFeatures& f, Matches* m, SE3* T_w_c);
  /// Keyframes relocalisation tries, most promising first.
  std::vector<Id> relocalisationCandidates(const FrameFeatures& f);
  /// A stored keyframe's words (indexed on first use for a loaded map's keyframes).
  const FrameWords* keyframeWords(Id kf);
  /// The current frame's words, computed once per frame.
  const FrameWords& frameWords(const FrameFeatures& f);
  std::vector<Id> localKeyframes();
  /// The reference keyframe's covisible keyframes (covisible_min_shared), computed once per
  /// reference: the count runs over every observation of its points, which grows with every
  /// revisit of the place, while what changes it between keyframes (culling, BA outliers) is
  /// rare. Caller holds the map lock.
  const std::vector<std::pair<Id, int>>& referenceCovisible();
  LocalMap collectLocalMap();
  /// collectLocalMap under the map lock, timed as search.
  LocalMap takeLocalMap();
  /// Projection search of `local` (taken once per frame: both passes search the same map).
  /// `record_visible`: fill m->visible_* with the landmarks predicted in the image.
  void searchLocalMap(const LocalMap& local, const SE3& T_w_c, const FrameFeatures& f, double radius, Matches* m,
                      bool record_visible);
  /// Counts the landmarks in m->visible_* as visible and the matched ones as found.
  void countVisibleAndFound(const Matches& m, TrackingResult* r);
  PoseOnlyResult optimizePose(const SE3& T_w_c, const FrameFeatures& f, Matches* m);
  Attempt relocalize(const FrameFeatures& f, Matches* m);
  /// The keyframe sharing the most landmarks with the tracked frame (`fallback` if none):
  /// the reference in localisation, the place of the frame for the keyframe rules.
  Id keyframeSharingMost(const Matches& m, Id fallback) const;
  bool needKeyframe(const SE3& T_w_c, int inliers) const;
  /// The landmarks keyframe `kf` was tracked with when it was made (map lock held).
  int landmarksOf(Id kf) const;
  /// `kf` is one of the local_keyframes newest keyframes (map lock held).
  bool isRecentKeyframe(Id kf) const;
  Id makeKeyframe(TimeNs t_ns, const SE3& T_w_c, const FrameFeatures& f, const Matches& m);

  Map* map_;
  PinholeCamera camera_;
  TrackerOptions options_;
  PoseOptimizer optimizer_;
  KeyframePlaces places_;
  bool have_frame_words_ = false;  // frame_words_ describes the frame being tracked
  FrameWords frame_words_;

  bool have_last_ = false, have_velocity_ = false, lost_ = false;
  SE3 T_w_last_, T_prev_last_;  // the last frame in the one before it: the constant-velocity step
  TimeNs t_last_ns_ = 0;  // stamp of the last tracked frame
  Id reference_kf_ = kNoId;
  int frames_since_kf_ = 0;
  int reference_kf_landmarks_ = 0;
  Id place_kf_ = kNoId;  // the keyframe sharing the most landmarks with the last tracked frame
  std::unordered_map<Id, int> keyframe_landmarks_;  // per keyframe made here: the landmarks it was tracked with
  int lost_events_ = 0, relocalisations_ = 0, reanchors_ = 0;
  bool search_all_keyframes_ = false;  // relocalise against every keyframe (loaded map, not tracked yet)
  StageTimes times_;  // the current frame's stage times (searchLocalMap and optimise add to them)
  Id covisible_of_ = kNoId;  // the keyframe covisible_ was computed for
  std::vector<std::pair<Id, int>> covisible_;
  // Reused on every frame, so that the per-frame id sets allocate nothing once warmed up:
  // the local map's landmarks while it is collected, then the landmarks already matched.
  IdSet scratch_points_, scratch_lines_;
  size_t last_local_points_ = 0, last_local_lines_ = 0;  // the last local map's size, to size them
};

}  // namespace plslam
