// The configuration keys of tracking (tracker.) and of the dynamic filter (dynamic.): one
// line per field; the doc string is the field's documentation.
#include "core/option_table.h"
#include "dynamic/delaunay_motion.h"
#include "dynamic/dynamic_mask.h"
#include "dynamic/label_spread.h"
#include "dynamic/mask_propagation.h"
#include "dynamic/motion_check.h"
#include "frontend/dynamic_filter.h"
#include "frontend/tracker.h"
#include "optim/measurement.h"
#include "optim/pose_optimizer.h"

namespace plslam {

void bindTrackerOptions(OptionTable* t, TrackerOptions* o) {
  TrackerOptions& tr = *o;
  t->bind("tracker.min_init_points", &tr.min_init_points, "keypoints with depth needed to initialise");
  t->bind("tracker.max_depth_m", &tr.max_depth_m, "keypoints farther than this make no map points (m)");
  t->bind("tracker.min_inliers", &tr.min_inliers, "fewer pose inliers than this: lost");
  t->bind("tracker.wide_radius_px", &tr.wide_radius_px, "projection search radius around the motion-model prediction (px)");
  t->bind("tracker.narrow_radius_px", &tr.narrow_radius_px, "projection search radius after the first optimisation (px)");
  t->bind("tracker.max_descriptor_distance", &tr.max_descriptor_distance, "ORB Hamming distance accepted");
  t->bind("tracker.ratio", &tr.ratio, "best / second-best descriptor distance ratio");
  t->bind("tracker.max_line_descriptor_distance", &tr.max_line_descriptor_distance, "LBD Hamming distance accepted");
  t->bind("tracker.line_angle_deg", &tr.line_angle_deg, "max angle between a projected map line and a segment (deg)");
  t->bind("tracker.line_distance_px", &tr.line_distance_px, "max distance of segment endpoints to a projected line (px)");
  t->bind("tracker.local_keyframes", &tr.local_keyframes, "keyframes whose landmarks form the local map");
  t->bind("tracker.covisible_min_shared", &tr.covisible_min_shared,
          "keyframes sharing this many points with the reference keyframe join the local map");
  t->bind("tracker.near_plane_m", &tr.near_plane_m, "landmarks nearer the camera than this are not projected (m)");
  t->bind("tracker.keyframe_max_frames", &tr.keyframe_max_frames, "a keyframe at least every this many frames, except on a revisit (the frame shares most landmarks with an older keyframe than the newest)");
  t->bind("tracker.keyframe_min_frames", &tr.keyframe_min_frames, "never a keyframe more often than this");
  t->bind("tracker.keyframe_inlier_ratio", &tr.keyframe_inlier_ratio, "keyframe when inliers < ratio * the reference keyframe's");
  t->bind("tracker.keyframe_min_inliers", &tr.keyframe_min_inliers, "keyframe when fewer inliers than this");
  t->bind("tracker.keyframe_min_support", &tr.keyframe_min_support,
          "never a keyframe from a frame with fewer inliers than this (a weak pose would seed the map)");
  t->bind("tracker.keyframe_max_translation_m", &tr.keyframe_max_translation_m, "keyframe after moving this far from the reference keyframe (m)");
  t->bind("tracker.keyframe_max_rotation_deg", &tr.keyframe_max_rotation_deg, "keyframe after turning this much (deg)");
  t->bind("tracker.max_speed_m_s", &tr.max_speed_m_s,
          "a pose that moved the camera faster than this since the last tracked frame is refused (m/s)");
  t->bind("tracker.reference_fallback", &tr.reference_fallback,
          "when the motion model fails, match the reference keyframe through the vocabulary before giving up");
  t->bind("tracker.wide_fallback_factor", &tr.wide_fallback_factor,
          "then search the prediction in a window this many times wider (<= 1: no)");
  t->bind("tracker.relocalisation_fallback", &tr.relocalisation_fallback,
          "then relocalise this frame over the whole map (the last pose may be wrong: no speed limit) before giving up");
  t->bind("tracker.min_vocabulary_matches", &tr.min_vocabulary_matches,
          "point + line matches a keyframe needs for a fallback or relocalisation attempt");
  t->bind("tracker.min_pnp_points", &tr.min_pnp_points, "point matches (and PnP inliers) needed for a PnP pose (fewer: start from the prediction, lines carry the pose)");
  t->bind("tracker.pnp_iterations", &tr.pnp_iterations, "PnP RANSAC iterations");
  t->bind("tracker.pnp_error_px", &tr.pnp_error_px, "PnP RANSAC reprojection threshold (px)");
  t->bind("tracker.relocalisation_min_inliers", &tr.relocalisation_min_inliers,
          "pose inliers (points + lines) that accept a relocalisation");
  t->bind("tracker.relocalisation_recent_keyframes", &tr.relocalisation_recent_keyframes,
          "without a vocabulary: the recent keyframes relocalisation tries");
  t->bind("tracker.relocalisation_candidates", &tr.relocalisation.max_candidates,
          "keyframes of the whole map relocalisation tries, most similar first");
  t->bind("tracker.relocalisation_min_relative_score", &tr.relocalisation.min_relative_score,
          "and only those scoring at least this fraction of the most similar");
  t->bind("tracker.relocalisation_point_weight", &tr.relocalisation.point_weight,
          "weight of the ORB similarity when relocalisation ranks keyframes");
  t->bind("tracker.relocalisation_line_weight", &tr.relocalisation.line_weight,
          "weight of the LBD similarity (when both sides have lines)");
  t->bind("tracker.reanchor_after_s", &tr.reanchor_after_s,
          "lost this long (s) and not relocalised: track on from a new keyframe at the last pose (0: never)");
  bindPoseOptimizerOptions(t, "tracker.pose_", &tr.optimizer);
  bindMeasurementModel(t, "tracker.", "in pose optimisation", &tr.optimizer.model);
}

void bindDynamicFilterOptions(OptionTable* t, DynamicFilterOptions* o) {
  DynamicFilterOptions& d = *o;
  t->bind("dynamic.enabled", &d.enabled, "reject features on moving objects (geometry, Delaunay graph, instance masks)");
  t->bind("dynamic.segment_every", &d.segment_every, "segment every this many frames");
  t->bind("dynamic.compare_gap", &d.compare_gap, "check motion against the frame this many frames back (a slow walker moves too little between adjacent 30 Hz frames to be seen)");
  t->bind("dynamic.match_radius_px", &d.match_radius_px, "search radius for adjacent-frame keypoint matches (px)");
  t->bind("dynamic.predicted_search_px", &d.predicted_search_px,
          "when the tracker's prediction moves the earlier keypoints further than this (median, px), also match around the predicted positions, and take those matches where their motion has predicted_search_support times the inliers (0: never)");
  t->bind("dynamic.predicted_search_support", &d.predicted_search_support,
          "the matches around the prediction are taken only with at least this many times the inliers of those around the old positions (the prediction can help the check, not overrule it)");
  t->bind("dynamic.unmatched_search_px", &d.unmatched_search_px,
          "earlier keypoints the check left unmatched are searched this far (px) from where the estimated camera motion puts them, and judged by that motion (near walkers outrun match_radius_px; 0: never)");
  t->bind("dynamic.match_ratio", &d.match_ratio, "adjacent-frame matches need best < ratio * second-best Hamming distance (0.9 let repeated textures and edges give consistent mismatches)");
  t->bind("dynamic.match_max_distance", &d.match_max_distance, "ORB Hamming distance accepted for adjacent-frame matches");
  t->bind("dynamic.line_masked_fraction", &d.line_masked_fraction,
          "segments with more than this fraction of their length on dynamic pixels are removed");
  t->bind("dynamic.spread_labels", &d.spread_labels, "spread motion labels to unmatched keypoints over the Delaunay graph of all keypoints");
  t->bind("dynamic.spread_with_masks", &d.spread_with_masks, "spread labels also on frames with instance masks");
  t->bind("dynamic.replay_latency_frames", &d.latency_frames,
          "use masks exactly this many frames after the frame they were segmented on, waiting for them if needed (reproduces a slow segmenter; 0: as soon as ready)");
  t->bind("dynamic.propagate_masks", &d.propagate_masks, "carry late masks (threaded mode, or replay_latency_frames > 0) to the current frame by optical flow per instance; sequential mode without a latency never carries them");
  bindDynamicMaskOptions(t, "dynamic.", &d.mask);
  bindMotionCheckOptions(t, "dynamic.motion_", &d.motion);
  bindDelaunayMotionOptions(t, "dynamic.delaunay_", &d.delaunay);
  bindLabelSpreadOptions(t, "dynamic.spread_", &d.spread);
  bindFreeSpaceOptions(t, "dynamic.free_space_", &d.free_space);
  bindMaskPropagationOptions(t, "dynamic.propagation_", &d.propagation);
}

}  // namespace plslam
