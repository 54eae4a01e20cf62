// The configuration keys of the moving-object checks' options (bound under dynamic. by the
// run): one line per field, with the range a value must be in.
#include "core/option_table.h"
#include "dynamic/delaunay_motion.h"
#include "dynamic/dynamic_mask.h"
#include "dynamic/free_space_check.h"
#include "dynamic/label_spread.h"
#include "dynamic/mask_propagation.h"
#include "dynamic/motion_check.h"

namespace plslam {

namespace {
void bindNoise(OptionTable* t, const std::string& p, PointNoiseOptions* o) {
  t->bind(p + "pixel_sigma", &o->pixel_sigma, "keypoint position noise of the motion check (px, 1 sigma)", above(0));
  t->bind(p + "depth_sigma_quadratic", &o->depth_sigma_quadratic, "its depth noise: sigma_z = quadratic * z^2 + constant (1/m)", atLeast(0));
  t->bind(p + "depth_sigma_constant_m", &o->depth_sigma_constant, "... and the constant (m; also absorbs depth quantisation)", above(0));
}

void bindSurface(OptionTable* t, const std::string& p, SameSurfaceOptions* o, const std::string& what) {
  t->bind(p + "min_step_m", &o->min_step_m, what + ": depth step always taken as one surface (m)", atLeast(0));
  t->bind(p + "step_ratio", &o->ratio, what + ": depth step taken as one surface, fraction of the nearer depth", atLeast(0));
}
}  // namespace

void bindMotionCheckOptions(OptionTable* t, const std::string& p, MotionCheckOptions* o) {
  bindNoise(t, p, &o->noise);
  t->bind(p + "chi2_3d", &o->chi2_3d, "3D residual test, chi-square with 3 dof (16.27: 99.9 %)", above(0));
  t->bind(p + "chi2_2d", &o->chi2_2d, "reprojection test, chi-square with 2 dof (13.82: 99.9 %)", above(0));
  t->bind(p + "chi2_1d", &o->chi2_1d, "epipolar distance test, chi-square with 1 dof (10.83: 99.9 %)", above(0));
  t->bind(p + "min_correspondences", &o->min_correspondences, "fewer adjacent-frame matches: no check", atLeast(3));
  t->bind(p + "min_with_depth", &o->min_with_depth, "fewer matches with depth in both frames: no check", atLeast(3));
  t->bind(p + "min_inliers", &o->min_inliers, "fewer inliers of the best camera motion: no consensus", atLeast(3));
  t->bind(p + "min_inlier_ratio", &o->min_inlier_ratio, "... or inliers below this fraction of the matches with depth", within(0, 1));
  t->bind(p + "max_iterations", &o->max_iterations, "RANSAC hypotheses at most", atLeast(1));
  t->bind(p + "min_iterations", &o->min_iterations, "RANSAC hypotheses at least (50: 99.9 % for half outliers)", atLeast(1));
  t->bind(p + "confidence", &o->confidence, "adaptive stop: probability of one all-inlier sample", Range{0, 1, true});
  t->bind(p + "seed", &o->seed, "RANSAC random stream (deterministic results)");
  t->bind(p + "min_sample_side_m", &o->min_sample_side_m, "minimal samples need all three sides this long (m)", atLeast(0));
  t->bind(p + "min_sample_sine", &o->min_sample_sine, "... and a triangle this far from collinear (sine of its smallest angle)", within(0, 1));
  t->bind(p + "rank_quantile", &o->rank_quantile, "hypotheses ranked by this quantile of their chi-square values (0.5: least median)", Range{0, 1, true});
  t->bind(p + "prior_rank_quantile", &o->prior_rank_quantile, "the quantile with a motion prior (it rules out the object's motion, so the background may be a minority)", Range{0, 1, true});
  t->bind(p + "adapt_noise_scale", &o->adapt_noise_scale, "scale the thresholds by how clean the data are against the noise model");
  t->bind(p + "min_noise_scale", &o->min_noise_scale, "lower bound of that scale (exact synthetic depth would drive it to 0)", above(0));
  t->bind(p + "max_noise_scale", &o->max_noise_scale, "upper bound of that scale", above(0));
  t->bind(p + "refine_iterations", &o->refine_iterations, "weighted refits on the inliers of each new best hypothesis", atLeast(0));
  t->bind(p + "prior_max_displacement_m", &o->prior_max_displacement_m,
          "with a prior: hypotheses moving a point farther than this from the prior's place are discarded (m)", above(0));
  t->bind(p + "prior_fallback", &o->prior_fallback, "with a prior and no consensus near it, retry without the prior");
  t->bind(p + "min_epipolar_baseline_m", &o->min_epipolar_baseline_m, "below this translation, features without depth use rotation transfer (m)", atLeast(0));
  t->bind(p + "min_scene_depth_m", &o->min_scene_depth_m, "nearest depth assumed for rotation transfer's parallax allowance (m)", above(0));
}

void bindDelaunayMotionOptions(OptionTable* t, const std::string& p, DelaunayMotionOptions* o) {
  t->bind(p + "chi2_length", &o->chi2_length, "graph edge broken when its length change exceeds this chi-square (1 dof)", above(0));
  t->bind(p + "static_group_fraction", &o->static_group_fraction,
          "without a camera motion, rigid groups with this fraction of the features, and the largest, are static", within(0, 1));
  t->bind(p + "min_region_features", &o->min_region_features, "moving graph regions smaller than this are not reported (their features stay flagged)", atLeast(1));
  bindSurface(t, p + "region_", &o->region_surface, "graph regions");
}

void bindLabelSpreadOptions(OptionTable* t, const std::string& p, LabelSpreadOptions* o) {
  t->bind(p + "passes", &o->passes, "rounds of label spreading (graph rings; 0: none)", atLeast(0));
  t->bind(p + "max_edge_px", &o->max_edge_px, "longer graph edges spread nothing (px)", above(0));
  t->bind(p + "min_still_neighbours", &o->min_still_neighbours,
          "a moving keypoint with no moving graph neighbour and this many still ones is a mismatch", atLeast(0));
  bindSurface(t, p, &o->surface, "label spreading");
}

void bindDynamicMaskOptions(OptionTable* t, const std::string& p, DynamicMaskOptions* o) {
  t->bind(p + "moving_fraction", &o->moving_fraction, "an instance moves when this fraction of its checked features move", within(0, 1));
  t->bind(p + "min_moving_features", &o->min_moving_features, "... and at least this many of them", atLeast(1));
  t->bind(p + "min_checked_features", &o->min_checked_features, "fewer checked features: the class prior decides", atLeast(0));
  t->bind(p + "static_classes_can_move", &o->static_classes_can_move, "geometry may declare an instance of a static class (a pushed chair) moving");
  t->bind(p + "use_delaunay_evidence", &o->use_delaunay_evidence, "features without a geometric check take the Delaunay graph's verdict");
  t->bind(p + "region_inside_fraction", &o->region_inside_fraction,
          "graph regions with this fraction of their features on instances are left to the instances", within(0, 1));
  t->bind(p + "region_min_checked", &o->region_min_checked, "a region is contradicted only when this many of its features were checked", atLeast(0));
  t->bind(p + "region_min_moving_fraction", &o->region_min_moving_fraction, "... and fewer than this fraction of them move", within(0, 1));
  t->bind(p + "dilate_px", &o->dilate_px, "dynamic areas grow by this many pixels (mask borders, depth edges)", atLeast(0));
  t->bind(p + "moving_area_dilate_px", &o->moving_area_dilate_px, "the spread moving area grows by this many pixels", atLeast(0));
  t->bind(p + "feature_radius_px", &o->feature_radius_px, "moving features outside dynamic areas mask a disc this wide (px; 0: flag only)", atLeast(0));
}

void bindMaskPropagationOptions(OptionTable* t, const std::string& p, MaskPropagationOptions* o) {
  t->bind(p + "max_corners", &o->max_corners, "corners tracked per instance to carry it (their median moves it; more cost more)", atLeast(1));
  t->bind(p + "corner_quality", &o->corner_quality, "Shi-Tomasi quality, relative to the instance's best corner", Range{0, 1, true});
  t->bind(p + "corner_distance_px", &o->corner_distance_px, "minimum distance between an instance's corners (px)", atLeast(0));
  t->bind(p + "erode_px", &o->erode_px, "corners at least this far inside the instance's outline (px)", atLeast(0));
  t->bind(p + "window_px", &o->window_px, "Lucas-Kanade window side (px)", atLeast(3));
  t->bind(p + "pyramid_levels", &o->pyramid_levels, "Lucas-Kanade pyramid levels above the image (a near walker moves tens of pixels a frame)", atLeast(0));
  t->bind(p + "min_corners", &o->min_corners, "an instance with fewer tracked corners is not moved", atLeast(1));
  t->bind(p + "interior_margin_fraction", &o->interior_margin_fraction,
          "features join a carried instance only this fraction of the carried distance inside its outline", atLeast(0));
  t->bind(p + "max_interior_margin_px", &o->max_interior_margin_px, "... and at most this far inside (px)", atLeast(0));
}

void bindFreeSpaceOptions(OptionTable* t, const std::string& p, FreeSpaceOptions* o) {
  t->bind(p + "enabled", &o->enabled, "flag unmatched keypoints in space the earlier depth image saw empty, and the unjudged rest of their surface (off: on static fr1_xyz it rejects 43 % of the keypoints, against 12 %)");
  t->bind(p + "window_radius_px", &o->window_radius_px,
          "the earlier depth is the nearest within this many pixels of the projection", atLeast(0));
  t->bind(p + "sigmas", &o->sigmas, "a keypoint must be this many depth-noise sigmas in front of it", above(0));
  t->bind(p + "min_gap_m", &o->min_gap_m, "... and at least this far in front (m)", atLeast(0));
  t->bind(p + "min_valid_fraction", &o->min_valid_fraction, "fraction of the window with depth, or no verdict",
          within(0, 1));
}

}  // namespace plslam
