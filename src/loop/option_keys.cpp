// The configuration keys of loop verification's options (bound under loop. by the run): one
// line per field, with the range a value must be in.
#include "core/option_table.h"
#include "loop/rigid_ransac.h"
#include "loop/semantic_match.h"

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

}  // namespace plslam
