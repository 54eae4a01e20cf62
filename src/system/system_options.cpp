// The configuration keys of a run: every option a YAML configuration file may set, bound
// to its field (its default is the field's initial value). Keep one line per field.
#include "system/system.h"

namespace plslam {

namespace {

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

// The dynamic filter, and the segmenter it drives.
void bindDynamicOptions(OptionTable* t, SystemOptions* o) {
  DynamicFilterOptions& d = o->dynamic;
  t->bind("dynamic.enabled", &d.enabled, "reject features on moving objects (geometry, Delaunay graph, instance masks)");
  t->bind("dynamic.segment_every", &d.segment_every, "segment every this many frames");
  t->bind("dynamic.compare_gap", &d.compare_gap, "check motion against the frame this many frames back (a slow walker moves too little between adjacent 30 Hz frames to be seen)");
  t->bind("dynamic.match_radius_px", &d.match_radius_px, "search radius for adjacent-frame keypoint matches (px)");
  t->bind("dynamic.match_ratio", &d.match_ratio, "adjacent-frame matches need best < ratio * second-best Hamming distance (0.9 let repeated textures and edges give consistent mismatches)");
  t->bind("dynamic.match_max_distance", &d.match_max_distance, "ORB Hamming distance accepted for adjacent-frame matches");
  t->bind("dynamic.line_masked_fraction", &d.line_masked_fraction,
          "segments with more than this fraction of their length on dynamic pixels are removed");
  t->bind("dynamic.spread_labels", &d.spread_labels, "spread motion labels to unmatched keypoints over the Delaunay graph of all keypoints");
  t->bind("dynamic.spread_with_masks", &d.spread_with_masks, "spread labels also on frames with instance masks");
  t->bind("dynamic.replay_latency_frames", &d.latency_frames,
          "use masks exactly this many frames after the frame they were segmented on, waiting for them if needed (reproduces a slow segmenter; 0: as soon as ready)");
  t->bind("dynamic.propagate_masks", &d.propagate_masks, "carry late masks (threaded mode, or replay_latency_frames > 0) to the current frame by optical flow per instance; sequential mode without a latency never carries them");
  t->bind("dynamic.yolo_confidence", &o->segmenter.yolo.confidence, "YOLOv8-seg minimum class score");
  t->bind("dynamic.yolo_nms_iou", &o->segmenter.yolo.nms_iou, "YOLOv8-seg class-aware NMS overlap");
  t->bind("dynamic.yolo_mask_threshold", &o->segmenter.yolo.mask_threshold,
          "YOLOv8-seg mask probability above which a pixel is the instance's");
  t->bind("dynamic.yolo_max_instances", &o->segmenter.yolo.max_instances, "YOLOv8-seg instances kept per image (the best scores)");
  t->bind("dynamic.yolo_input_size", &o->segmenter.yolo.input_size,
          "YOLOv8-seg square input side for a model whose input size is symbolic (0: read it from the model)");
  bindSegmenterOptions(t, &o->segmenter);
  bindDynamicMaskOptions(t, "dynamic.", &d.mask);
  bindMotionCheckOptions(t, "dynamic.motion_", &d.motion);
  bindDelaunayMotionOptions(t, "dynamic.delaunay_", &d.delaunay);
  bindLabelSpreadOptions(t, "dynamic.spread_", &d.spread);
  bindMaskPropagationOptions(t, "dynamic.propagation_", &d.propagation);
}

// Loop closure, with the system switches of the threads that run behind tracking.
void bindLoopOptions(OptionTable* t, SystemOptions* o) {
  LoopOptions& l = o->loop;
  t->bind("system.use_loop", &o->use_loop, "loop closure (place recognition, verification, pose graph)");
  t->bind("system.refine_frames", &o->refine_frames, "re-estimate each frame's pose once local BA has refined its landmarks");
  t->bind("system.refine_after_keyframes", &o->refine_after_keyframes, "refine a frame when this many keyframes have been made since it");
  t->bind("system.refine_after_frames", &o->refine_after_frames, "... or this many frames");
  t->bind("system.background_nice", &o->background_nice,
          "nice value (0-19) of the mapping and loop threads, so that tracking wins the cores when both want them");
  t->bind("loop.vocabulary", &l.vocabulary, "bag-of-words vocabulary of loop closure and relocalisation (empty: vocab/plslam_orb_lbd.voc of the sources)");
  t->bind("loop.point_weight", &l.point_weight, "weight of the ORB similarity in the combined score");
  t->bind("loop.line_weight", &l.line_weight, "weight of the LBD similarity in the combined score (0 when either keyframe has no lines)");
  t->bind("loop.min_normalised_score", &l.min_normalised_score, "candidates need score / best covisible score above this");
  t->bind("loop.min_score", &l.min_score, "candidates need a combined score above this");
  t->bind("loop.exclude_recent", &l.exclude_recent, "the last keyframes before the query are never candidates");
  t->bind("loop.max_candidates", &l.max_candidates, "best candidates examined per keyframe");
  t->bind("loop.consistency", &l.consistency, "consecutive keyframes that must see the place");
  t->bind("loop.use_semantics", &l.use_semantics, "weigh candidates with the keyframes' segmented instances");
  t->bind("loop.min_matches", &l.min_matches, "ORB matches with depth needed for verification");
  t->bind("loop.min_inliers", &l.min_inliers, "3D-3D RANSAC inliers needed");
  t->bind("loop.min_inlier_ratio", &l.min_inlier_ratio, "RANSAC inliers / matches needed");
  t->bind("loop.edge_sigma_trans_m", &l.edge_sigma_trans_m, "pose-graph edge sigma, translation (m)");
  t->bind("loop.edge_sigma_rot_deg", &l.edge_sigma_rot_deg, "pose-graph edge sigma, rotation (deg)");
  t->bind("loop.fuse_duplicates", &l.fuse_duplicates, "merge map points seen at both ends of a loop");
  t->bind("loop.covisible_exclude_min_shared", &l.covisible_exclude_min_shared,
          "keyframes sharing this many points with the query are not loop candidates");
  t->bind("loop.line_max_distance", &l.line_max_distance, "LBD distance accepted for a line in the loop's verification");
  t->bind("loop.max_depth_m", &l.max_depth_m, "keypoints farther than this are not used to verify a loop (m)");
  t->bind("loop.covisibility_edge_min_shared", &l.covisibility_edge_min_shared,
          "keyframe pairs sharing this many points get a pose-graph edge");
  t->bind("loop.min_keyframes_between_loops", &l.min_keyframes_between_loops, "keyframes after an accepted loop before the next");
  t->bind("loop.global_ba", &l.global_ba, "a bundle adjustment of every keyframe and point after the pose graph");
  bindSemanticOptions(t, "loop.semantic_", &l.semantic);
  bindBruteForceOptions(t, "loop.match_", &l.matching);
  bindRigidRansacOptions(t, "loop.ransac_", &l.ransac);
  bindPoseGraphOptions(t, "loop.pose_graph_", &l.pose_graph);
  bindBundleAdjusterOptions(t, "loop.global_ba_", &l.ba);
  bindMeasurementModel(t, "loop.global_ba_", "in the global BA", &l.ba.model);
}

void bindDenseOptions(OptionTable* t, DenseOptions* o) {
  DenseOptions& dn = *o;
  t->bind("dense.enabled", &dn.enabled, "make a dense cloud per keyframe (needed for plslam run/export dense products)");
  t->bind("dense.min_depth_m", &dn.min_depth_m, "pixels nearer than this are left out of the clouds (m)");
  t->bind("dense.max_depth_m", &dn.max_depth_m, "pixels farther than this are left out of the clouds (m)");
  t->bind("dense.pixel_stride", &dn.pixel_stride, "use every n-th pixel in u and v");
  t->bind("dense.edge_jump_ratio", &dn.edge_jump_ratio, "drop flying pixels: depth differing from a 4-neighbour's by more than this fraction of it (0 = keep)");
  t->bind("dense.smooth_radius_px", &dn.smooth_radius_px, "depth denoising: inverse depth averaged over a (2r+1)^2 window of similar depths, r in px (0 = off)");
  t->bind("dense.depth_sigma_coeff", &dn.depth_sigma_coeff, "depth noise sigma = coeff * z^2, gates the denoising window (1/m)");
  t->bind("dense.keyframe_voxel_m", &dn.keyframe_voxel_m, "voxel size of each keyframe's cloud (m, 0 = none)");
  t->bind("dense.fused_voxel_m", &dn.fused_voxel_m, "voxel size of the fused world cloud (m, 0 = keep every point)");
  t->bind("dense.min_voxel_points", &dn.min_voxel_points, "fused voxels with fewer points are dropped");
  t->bind("dense.octree_resolution_m", &dn.octree_resolution_m, "OctoMap leaf size (m)");
  t->bind("dense.max_range_m", &dn.max_range_m, "OctoMap rays are cut at this range; farther points only mark free space (m, <= 0: none)");
  t->bind("dense.prob_hit", &dn.prob_hit, "OctoMap occupancy probability of a ray end");
  t->bind("dense.prob_miss", &dn.prob_miss, "OctoMap occupancy probability along a ray");
  t->bind("dense.occupied_thresh", &dn.occupied_thresh, "OctoMap voxels above this probability are occupied");
  t->bind("dense.floor", &dn.floor, "floor plane for the grid: ransac (lowest level plane) or gravity (the first camera's image up)");
  t->bind("dense.floor_max_tilt_deg", &dn.floor_max_tilt_deg, "ransac floor: max angle to the first camera's up (deg)");
  t->bind("dense.floor_inlier_m", &dn.floor_inlier_m, "ransac floor: inlier distance (m)");
  t->bind("dense.floor_search_fraction", &dn.floor_search_fraction,
          "ransac floor: searched among this lowest fraction of the points along the prior up (1: all)");
  t->bind("dense.floor_min_fraction", &dn.floor_min_fraction, "ransac floor: fraction of the searched points a floor needs");
  t->bind("dense.floor_max_above_base_m", &dn.floor_max_above_base_m,
          "ransac floor with calibration.camera_to_base: a level plane higher than this above the base's origin is no "
          "floor (the robot stands on it); none left: the base's own plane (m)");
  t->bind("dense.grid_min_height_m", &dn.grid_min_height_m, "2D grid: lower end of the obstacle band above the floor (m)");
  t->bind("dense.grid_max_height_m", &dn.grid_max_height_m, "2D grid: upper end of the obstacle band above the floor (m)");
  t->bind("dense.grid_resolution_m", &dn.grid_resolution_m, "2D grid cell size (m)");
  t->bind("dense.grid_occupied_thresh", &dn.grid_occupied_thresh, "map YAML occupied_thresh");
  t->bind("dense.grid_free_thresh", &dn.grid_free_thresh, "map YAML free_thresh");
  t->bind("dense.live_every_keyframes", &dn.live_every_keyframes,
          "maps while running: update the dense products after this many new keyframes (0 = not by count)");
  t->bind("dense.live_every_s", &dn.live_every_s,
          "maps while running: update this many seconds after the last update when something is new "
          "(0 = not by time; both 0 = only at the end)");
  t->bind("dense.live_nice", &dn.live_nice, "maps while running: nice value of their thread (0..19; 19 = idle cycles)");
}

void bindCalibrationOptions(OptionTable* t, SystemOptions* o) {
  t->bind("calibration.camera_to_base", &o->camera_to_base,
          "camera-to-base file of plslam calib base: the map frame's origin is then on the floor below the base, x its "
          "forward, and trajectory_base.txt is written (empty: none)");
  t->bind("calibration.depth_scale", &o->depth_correction.scale,
          "depth correction of plslam calib depth: measured = scale * true + offset (1: none)");
  t->bind("calibration.depth_offset_m", &o->depth_correction.offset_m, "... and its offset (m, 0: none)");
}

void bindMapperOptions(OptionTable* t, LocalMapperOptions* o) {
  LocalMapperOptions& m = *o;
  t->bind("mapper.local_ba", &m.local_ba, "run the local bundle adjustment");
  t->bind("mapper.ba_keyframes", &m.ba_keyframes, "keyframes optimised together in local BA");
  t->bind("mapper.ba_fixed_keyframes", &m.ba_fixed_keyframes, "further keyframes held fixed around them");
  t->bind("mapper.cull_found_ratio", &m.cull_found_ratio, "landmarks found in fewer predicted frames than this are culled");
  t->bind("mapper.cull_single_after", &m.cull_single_after, "points seen by one keyframe are culled this many keyframes later");
  t->bind("mapper.cull_min_visible", &m.cull_min_visible, "the found ratio is judged once a landmark was predicted this often");
  t->bind("mapper.min_covisible_points", &m.min_covisible_points, "shared points that make two keyframes covisible (local BA window)");
  bindBundleAdjusterOptions(t, "mapper.ba_", &m.ba);
  bindMeasurementModel(t, "mapper.", "in local BA", &m.ba.model);
  bindLineFitOptions(t, "mapper.line_", &m.line_fit);
}

}  // namespace

// One section after the other, in this order: the table lists (and writes) keys in binding order.
void bindOptions(OptionTable* t, SystemOptions* o) {
  t->bind("system.sequential", &o->sequential, "run all stages on one thread in a fixed order (deterministic)");
  t->bind("system.use_lines", &o->use_lines, "use line features in tracking and mapping");
  t->bind("system.mapping_queue", &o->mapping_queue, "keyframes waiting for local mapping before tracking waits");

  bindFeatureOptions(t, &o->features);
  bindTrackerOptions(t, &o->tracker);
  bindDynamicOptions(t, o);
  bindLoopOptions(t, o);
  bindDenseOptions(t, &o->dense);
  bindCalibrationOptions(t, o);
  bindMapperOptions(t, &o->mapper);
}

}  // namespace plslam
