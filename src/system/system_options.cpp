// The configuration keys of a run: every option a YAML configuration file may set, bound
// to its field (its default is the field's initial value). Keep one line per field.
#include "system/system.h"

namespace plslam {

void bindOptions(OptionTable* t, SystemOptions* o) {
  t->bind("system.sequential", &o->sequential, "run all stages on one thread in a fixed order (deterministic)");
  t->bind("system.use_lines", &o->use_lines, "use line features in tracking and mapping");
  t->bind("system.mapping_queue", &o->mapping_queue, "keyframes waiting for local mapping before tracking waits");

  bindFeatureOptions(t, &o->features);

  TrackerOptions& tr = o->tracker;
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
  t->bind("tracker.keyframe_max_frames", &tr.keyframe_max_frames, "a keyframe at least every this many frames");
  t->bind("tracker.keyframe_min_frames", &tr.keyframe_min_frames, "never a keyframe more often than this");
  t->bind("tracker.keyframe_inlier_ratio", &tr.keyframe_inlier_ratio, "keyframe when inliers < ratio * the reference keyframe's");
  t->bind("tracker.keyframe_min_inliers", &tr.keyframe_min_inliers, "keyframe when fewer inliers than this");
  t->bind("tracker.keyframe_max_translation_m", &tr.keyframe_max_translation_m, "keyframe after moving this far (m)");
  t->bind("tracker.keyframe_max_rotation_deg", &tr.keyframe_max_rotation_deg, "keyframe after turning this much (deg)");
  t->bind("tracker.pose_rounds", &tr.optimizer.rounds, "pose optimisation outlier rounds");
  t->bind("tracker.pose_iterations", &tr.optimizer.iterations_per_round, "solver iterations per round");
  t->bind("tracker.use_depth", &tr.optimizer.model.use_depth, "depth residuals in pose optimisation");
  t->bind("tracker.depth_sigma_coeff", &tr.optimizer.model.depth_sigma_coeff, "depth sigma = coeff * z^2 in pose optimisation (1/m)");

  DynamicFilterOptions& d = o->dynamic;
  t->bind("dynamic.enabled", &d.enabled, "reject features on moving objects (geometry, Delaunay graph, instance masks)");
  t->bind("dynamic.segment_every", &d.segment_every, "segment every this many frames");
  t->bind("dynamic.compare_gap", &d.compare_gap, "check motion against the frame this many frames back");
  t->bind("dynamic.match_radius_px", &d.match_radius_px, "search radius for adjacent-frame keypoint matches (px)");
  t->bind("dynamic.moving_fraction", &d.mask.moving_fraction, "an instance moves when this fraction of its checked features move");
  t->bind("dynamic.min_checked_features", &d.mask.min_checked_features, "fewer checked features: the class prior decides");
  t->bind("dynamic.dilate_px", &d.mask.dilate_px, "dynamic areas grow by this many pixels");
  t->bind("dynamic.yolo_confidence", &o->segmenter.yolo.confidence, "YOLOv8-seg minimum class score");
  t->bind("dynamic.yolo_nms_iou", &o->segmenter.yolo.nms_iou, "YOLOv8-seg class-aware NMS overlap");

  LocalMapperOptions& m = o->mapper;
  t->bind("mapper.local_ba", &m.local_ba, "run the local bundle adjustment");
  t->bind("mapper.ba_keyframes", &m.ba_keyframes, "keyframes optimised together in local BA");
  t->bind("mapper.ba_fixed_keyframes", &m.ba_fixed_keyframes, "further keyframes held fixed around them");
  t->bind("mapper.ba_iterations", &m.ba.max_iterations, "local BA iterations (robust pass)");
  t->bind("mapper.ba_refine_iterations", &m.ba.refine_iterations, "local BA iterations without outliers");
  t->bind("mapper.depth_sigma_coeff", &m.ba.model.depth_sigma_coeff, "depth sigma = coeff * z^2 in local BA (1/m)");
  t->bind("mapper.ba_max_time_s", &m.ba.max_time_s, "local BA time budget, seconds (0 = none)");
  t->bind("mapper.cull_found_ratio", &m.cull_found_ratio, "landmarks found in fewer predicted frames than this are culled");
  t->bind("mapper.cull_single_after", &m.cull_single_after, "points seen by one keyframe are culled this many keyframes later");
  t->bind("mapper.line_sample_step_px", &m.line_fit.sample_step_px, "spacing of depth samples along a segment (px)");
  t->bind("mapper.line_min_inlier_ratio", &m.line_fit.min_inlier_ratio, "fraction of valid samples a fitted 3D line must explain");
  t->bind("mapper.line_max_depth_m", &m.line_fit.max_depth_m, "depth samples beyond this are ignored (m)");
}

}  // namespace plslam
