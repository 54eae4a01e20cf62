// Loop closure on keyframes: place recognition with bags of ORB and LBD words, semantic
// instance agreement, geometric verification with depth, pose-graph correction.
//
// Per new keyframe (processKeyframe, on the mapping thread after the local mapper):
//  1. its ORB and LBD bags of words are computed and it is added to the database;
//  2. every earlier keyframe that is neither covisible with it nor among the last
//     `exclude_recent` keyframes is scored: s = (w_p s_orb + w_l s_lbd) / (w_p + w_l)
//     (w_l = 0 when either keyframe has no lines), normalised by the best score of the query
//     against its covisible neighbours (ORB-SLAM's normalisation: a place is recognised
//     when it looks about as alike as the frames the camera just saw); then multiplied by
//     the semantic factor (semantic_match.h) when instances are known;
//  3. candidates above `min_normalised_score` must be consistent over `consistency`
//     consecutive keyframes (their covisibility groups overlap, as in ORB-SLAM);
//  4. geometric verification: ORB descriptor matches (ratio + mutual) on the keyframes'
//     map points, 3D-3D RANSAC + Umeyama refinement (rigid_ransac.h); the map lines that
//     agree with that pose join a second RANSAC whose refinement fits points and lines;
//     thresholds on matches, point inliers and inlier ratio; then the instance positions are
//     checked under the found pose (a semantic contradiction rejects the loop);
//  5. the first accepted candidate closes the loop: the query keyframe's covisibility group
//     is moved by the loop correction, a pose graph over all keyframes (consecutive,
//     strong covisibility and all loop edges so far) is optimised with the oldest
//     keyframe fixed, map points and lines move with their reference (first) keyframe, and
//     the inlier point pairs observed by both places are fused.
// Every examined candidate ends with a LoopStatus and a reason.
//
// Thread safety: one LoopCloser per map, used from one thread (the System's loop thread);
// it holds the map's mutex while it reads keyframes and while it applies a correction, never
// while it solves: tracking and local mapping go on during a correction's solves.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "features/matching.h"
#include "place/keyframe_database.h"
#include "loop/rigid_ransac.h"
#include "loop/semantic_match.h"
#include "place/vocabulary.h"
#include "optim/bundle_adjuster.h"
#include "optim/pose_graph.h"

namespace plslam {

class OptionTable;

enum class LoopStatus {
  kAccepted,             ///< verified and corrected
  kLowScore,             ///< similarity below the threshold
  kNoConsistentGroup,    ///< not seen consistently over enough consecutive keyframes
  kTooSoonAfterLoop,     ///< fewer than min_keyframes_between_loops keyframes since the last loop
  kTooFewMatches,        ///< too few descriptor matches with depth
  kTooFewInliers,        ///< 3D-3D RANSAC left too few inliers
  kRejectedBySemantics,  ///< the instances contradict the place (before or after the pose)
  kCorrectionFailed,     ///< the pose graph did not converge
};
constexpr int kLoopStatusCount = 8;
const char* toString(LoopStatus status);

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindLoopOptions (loop/option_keys.cpp). `plslam run --print-config` lists them.
struct LoopOptions {
  std::string vocabulary;
  double point_weight = 0.6;
  double line_weight = 0.4;
  double min_normalised_score = 0.65;
  double min_score = 0.02;
  int exclude_recent = 10;
  int covisible_exclude_min_shared = 1;
  int max_candidates = 3;
  int consistency = 2;
  bool use_semantics = true;
  SemanticOptions semantic;          ///< instance matching
  BruteForceOptions matching{64, 0.8f, true};  ///< ORB matching for verification
  // Loose: the points' pose chose the line, and LBD changes with the viewpoint across a loop.
  int line_max_distance = 110;
  double max_depth_m = 6.0;
  RigidRansacOptions ransac;         ///< 3D-3D RANSAC
  int min_matches = 30;
  int min_inliers = 25;
  double min_inlier_ratio = 0.3;
  double edge_sigma_trans_m = 0.02;
  double edge_sigma_rot_deg = 1.0;
  int covisibility_edge_min_shared = 50;
  bool fuse_duplicates = true;
  int min_keyframes_between_loops = 5;
  PoseGraphOptions pose_graph;       ///< solver
  // ORB-SLAM's global BA. Lines follow their keyframe instead of entering it (docs/RESULTS.md,
  // "Design choices measured earlier"). Solved on a snapshot of the map without its lock,
  // applied in one short critical section (loop/map_correction.h).
  bool global_ba = true;
  BundleAdjusterOptions ba = globalBundleOptions();  ///< its solver (first keyframe fixed)

  /// Throws ConfigError naming the `loop.` key of the first value out of range (the loop
  /// closer checks on construction).
  void validate() const;

  static BundleAdjusterOptions globalBundleOptions() {
    BundleAdjusterOptions o;
    o.model.depth_sigma_coeff = kSolverDepthSigmaCoeff;  // as tracking and local mapping
    o.max_iterations = 10;
    o.refine_iterations = 5;
    o.max_time_s = 3.0;
    return o;
  }
};

/// Binds the loop.* keys (loop/option_keys.cpp).
void bindLoopOptions(OptionTable* table, LoopOptions* options);

/// One examined candidate.
struct LoopCandidate {
  Id query = kNoId, candidate = kNoId;
  double score_orb = 0, score_lbd = 0;
  double score = 0;            ///< combined
  double normalised = 0;       ///< combined / best covisible neighbour, times the semantic factor
  double semantic_factor = 1;
  int matches = 0, inliers = 0;  ///< ORB matches with depth, and RANSAC inliers among them
  int line_matches = 0, line_inliers = 0;  ///< lines paired under the pose, and inliers of the final fit
  SE3 T_query_candidate;       ///< the verified relative pose (when matched)
  LoopStatus status = LoopStatus::kLowScore;
  std::string reason;
};

/// What a correction changed: per keyframe, the pose change T_w_new * T_w_old^-1.
struct LoopCorrection {
  Id query = kNoId, match = kNoId;
  std::map<Id, SE3> T_new_old;
  double ms = 0;       ///< detection to applied correction, solves included
  double hold_ms = 0;  ///< of which the map (and tracking) were held: the critical sections only
};

struct LoopStats {
  int queries = 0;      ///< keyframes processed
  int candidates = 0;   ///< candidates examined
  int accepted = 0;
  int refused[kLoopStatusCount] = {};  ///< per LoopStatus
  std::vector<double> correction_ms;
  std::vector<double> correction_hold_ms;  ///< per correction, how long tracking and mapping waited for it
};

/// Similarity of two keyframes' bags as the loop closer computes it (before normalisation).
double combinedScore(double orb, double lbd, bool lines_in_both, const LoopOptions& options);


/// 3D positions of one keyframe's features in its camera frame, per feature index (NaN or
/// missing entries: unknown).
struct FeatureGeometry {
  std::vector<Eigen::Vector3d> points;  ///< per keypoint
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;  ///< per line: endpoints for p and q
};


/// Geometric verification of two keyframes' features with depth: ORB matches with
/// back-projected keypoints, 3D-3D RANSAC on them (rigid_ransac.h); then the lines whose 3D
/// segments are known in both are paired under that pose and the RANSAC runs again on
/// points and lines. Acceptance counts point inliers. Fills matches, inliers, line_matches,
/// line_inliers, T_query_candidate, status and reason of `c`; `inlier_pairs` (optional)
/// gets the (query keypoint, candidate keypoint) inlier pairs. `query_c` / `candidate_c` (optional): 3D positions to use instead
/// of the keypoints' depth, and the only source of 3D lines (the loop closer passes its
/// bundle-adjusted map points and its map lines, more accurate than one depth reading).
void verifyGeometry(const FrameFeatures& query, const FrameFeatures& candidate, const PinholeCamera& camera,
                    const LoopOptions& options, LoopCandidate* c,
                    std::vector<std::pair<int, int>>* inlier_pairs = nullptr, const FeatureGeometry* query_c = nullptr,
                    const FeatureGeometry* candidate_c = nullptr);

class LoopCloser {
 public:
  /// Throws ConfigError when the vocabulary cannot be loaded (naming the file).
  LoopCloser(Map* map, PinholeCamera camera, LoopOptions options);
  LoopCloser(Map* map, PinholeCamera camera, LoopOptions options, std::shared_ptr<const VocabularySet> vocabulary);

  /// Adds keyframe `id` and looks for a loop; returns the correction when one was closed.
  std::optional<LoopCorrection> processKeyframe(Id id);

  /// Adds every keyframe already in the map and not yet indexed (a loaded map) to the
  /// database, in id order, without looking for loops among them: places of an earlier
  /// session can then be recognised. Returns how many were added.
  int indexMapKeyframes();
  /// Keyframes in the database (read it while no keyframe is being processed).
  size_t indexedKeyframes() const { return database_.size(); }

  /// A correction is applied holding `guard` (locked before the map's mutex; may be null),
  /// and `hook` is called with it before the guard is released: the system re-anchors the
  /// tracker there, so no frame is tracked between the map's move and the tracker's.
  void setCorrectionHook(std::mutex* guard, std::function<void(const LoopCorrection&)> hook) {
    guard_ = guard;
    hook_ = std::move(hook);
  }

  /// A copy: safe from any thread while the loop thread runs.
  LoopStats stats() const {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    return stats_;
  }
  const std::vector<LoopCandidate>& log() const { return log_; }
  const LoopOptions& options() const { return options_; }
  const VocabularySet& vocabulary() const { return *vocabulary_; }

 private:
  /// What the search for a keyframe's loop keeps of it.
  struct LoopQuery {
    FrameFeatures features;
    std::vector<KeyframeInstance> instances;
    FeatureGeometry geometry;  ///< its landmarks in its camera frame
  };
  /// Steps 1-2: indexes keyframe `id` and scores the database against it (the best
  /// max_candidates, normalised, semantic factor applied). False when the keyframe is gone.
  bool scoreCandidates(Id id, LoopQuery* query, std::vector<LoopCandidate>* candidates);
  /// Step 3: the candidates above the threshold seen consistently; records the others.
  std::vector<LoopCandidate> consistentCandidates(std::vector<LoopCandidate> candidates);
  /// Steps 4-5: geometric (and semantic) verification, then the correction of the first
  /// candidate that passes; records every candidate examined.
  std::optional<LoopCorrection> verifyAndClose(const LoopQuery& query, std::vector<LoopCandidate> passed);
  /// A pose graph over every keyframe, taken from the map (caller holds its lock).
  struct PoseGraphSnapshot {
    std::vector<Id> ids;     ///< keyframes, ascending
    std::vector<SE3> T_w_c;  ///< their poses as taken
    PoseGraphProblem problem;
    SE3 correction;          ///< the loop's correction of the query's side (initial guess)
  };
  /// Pose graph (then global BA): each solved on a snapshot without the map lock and applied
  /// in a short critical section under the correction guard and the map lock.
  std::optional<LoopCorrection> correct(const LoopCandidate& c, const std::vector<std::pair<int, int>>& inlier_pairs);
  bool buildPoseGraph(const LoopCandidate& c, PoseGraphSnapshot* graph) const;
  /// Merges the loop's inlier point pairs (caller holds the map lock); returns how many.
  int fuseLoopPoints(const LoopCandidate& c, const std::vector<std::pair<int, int>>& inlier_pairs);
  /// The correction guard, locked (empty when there is none).
  std::unique_lock<std::mutex> lockForCorrection();
  void record(const LoopCandidate& c);
  /// Adds (or replaces) a keyframe's bags in the database, keeping order_ free of repeats.
  void index(Id id, const KeyframeBow& bow);
  /// Every keyframe and every map point seen twice (caller holds the map lock).
  BundleProblem globalBundleProblem(std::vector<Id>* kf_ids, std::vector<Id>* point_ids) const;
  /// Global BA on a snapshot, applied like the pose graph; composes its change into `correction`.
  void globalBundleAdjustment(LoopCorrection* correction);

  Map* map_;
  PinholeCamera camera_;
  LoopOptions options_;
  std::shared_ptr<const VocabularySet> vocabulary_;
  KeyframeDatabase database_;
  std::vector<Id> order_;  ///< keyframes in processing order
  struct Group {
    std::vector<Id> members;  ///< sorted
    int count = 0;
  };
  std::vector<Group> groups_;  ///< consistent groups of the previous keyframe
  struct LoopEdge {
    Id a, b;
    SE3 T_a_b;
  };
  std::vector<LoopEdge> loop_edges_;
  int keyframes_since_loop_ = 1 << 20;
  std::mutex* guard_ = nullptr;
  std::function<void(const LoopCorrection&)> hook_;
  mutable std::mutex stats_mutex_;  // guards stats_ (read by System::stats() mid-run)
  LoopStats stats_;
  std::vector<LoopCandidate> log_;
};

}  // namespace plslam
