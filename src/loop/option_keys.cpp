// The configuration keys of loop verification's options (bound under loop. by the run): one
// line per field, with the range a value must be in.
#include "core/option_table.h"
#include "features/matching.h"
#include "loop/loop_closer.h"
#include "loop/rigid_ransac.h"
#include "loop/semantic_match.h"
#include "optim/bundle_adjuster.h"
#include "optim/measurement.h"
#include "optim/pose_graph.h"

namespace plslam {

void bindSemanticOptions(OptionTable* t, const std::string& p, SemanticOptions* o) {
  t->bind(p + "max_image_offset", &o->max_image_offset, "instance box centres this far apart (fraction of the image diagonal) do not match", atLeast(0));
  t->bind(p + "max_depth_difference_m", &o->max_depth_difference_m, "instance centroid depths differing more do not match (m)", atLeast(0));
  t->bind(p + "max_position_error_m", &o->max_position_error_m, "3D disagreement allowed between matched instances (m)", above(0));
  t->bind(p + "min_matches", &o->min_matches, "fewer consistent instances never raise a score", atLeast(1));
  t->bind(p + "min_instances_to_refute", &o->min_instances_to_refute,
          "both keyframes need this many static instances for a disagreement to lower the score", atLeast(1));
  t->bind(p + "generic_weight", &o->generic_weight, "weight of a generic class's match (others weigh 1)", within(0, 1));
  t->bindList(p + "generic_classes", &o->generic_classes, "comma-separated common classes (COCO names) that weigh generic_weight");
  t->bind(p + "gain", &o->gain, "score *= 1 + gain * similarity when the instances agree", atLeast(0));
  t->bind(p + "penalty", &o->penalty, "score *= 1 - penalty when they disagree", within(0, 1));
}

void bindRigidRansacOptions(OptionTable* t, const std::string& p, RigidRansacOptions* o) {
  t->bind(p + "iterations", &o->iterations, "3D-3D RANSAC samples", atLeast(1));
  t->bind(p + "threshold_m", &o->threshold_m, "3D inlier distance at zero depth (m)", above(0));
  t->bind(p + "depth_coeff", &o->depth_coeff, "plus this times depth squared (1/m)", atLeast(0));
  t->bind(p + "refine_rounds", &o->refine_rounds, "least-squares refits on the inliers", atLeast(0));
  t->bind(p + "line_angle_deg", &o->line_angle_deg, "direction difference accepted for a line inlier (deg)", within(0, 90));
  t->bind(p + "seed", &o->seed, "sampling seed (deterministic results)");
}

void bindLoopOptions(OptionTable* t, LoopOptions* o) {
  LoopOptions& l = *o;
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

}  // namespace plslam
