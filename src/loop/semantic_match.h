// Semantic agreement of two keyframes from their segmented instances (KeyFrame::instances).
//
// Only static instances count (dynamic ones moved, or may have). Two instances can match
// only when they have the same class, their box centres lie within `max_image_offset` (a
// fraction of the image diagonal) and their depths agree within `max_depth_difference_m`;
// a one-to-one assignment keeps the closest boxes first. A set of matches is then checked
// for 3D consistency: either under a relative pose T_a_b (after geometric verification:
// |c_a - T_a_b c_b| within `max_position_error_m`) or, before it, by the relative geometry
// of instance pairs (|c_a1 - c_a2| against |c_b1 - c_b2|), keeping the largest consistent set.
//
// The similarity is the consistent matches' class weights over the larger instance count.
// Classes in `generic_classes` (chairs, cups...) weigh less, and evidence below
// `min_matches` consistent instances never raises a score: one shared chair does not make
// two places alike. Two keyframes that both show at least `min_instances_to_refute` static
// instances and agree on none lower the score instead.
//
// Stateless; thread-safe.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/map.h"
#include "core/se3.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindSemanticOptions (loop/option_keys.cpp). `plslam run --print-config` lists them.
struct SemanticOptions {
  double max_image_offset = 0.25;
  double max_depth_difference_m = 1.0;
  double max_position_error_m = 0.35;
  int min_matches = 2;
  int min_instances_to_refute = 2;
  double generic_weight = 0.3;
  std::vector<std::string> generic_classes = {"chair", "cup", "bottle", "book", "potted plant", "person", "tv", "laptop",
                                              "keyboard", "mouse", "dining table"};
  double gain = 0.5;
  double penalty = 0.5;
};

/// Binds `prefix` + "max_image_offset", ..., "generic_classes".
void bindSemanticOptions(OptionTable* table, const std::string& prefix, SemanticOptions* options);

/// One instance pair kept.
struct InstanceMatch {
  int a = -1, b = -1;  ///< indices into the two keyframes' instances
};

struct SemanticResult {
  std::vector<InstanceMatch> matches;  ///< consistent matches
  int static_a = 0, static_b = 0;      ///< static instances with a centroid in each keyframe
  double similarity = 0;               ///< weighted consistent matches / max(static_a, static_b), [0, 1]
  double factor = 1;                   ///< what the appearance score is multiplied by
  bool refuted = false;                ///< both had enough instances and none agreed
};

/// `image_diagonal`: of the image the boxes live in (pixels). `T_a_b`: a relative pose to
/// check positions with (none: the pair-distance test).
SemanticResult matchInstances(const std::vector<KeyframeInstance>& a, const std::vector<KeyframeInstance>& b,
                              double image_diagonal, const SemanticOptions& options,
                              const std::optional<SE3>& T_a_b = std::nullopt);

}  // namespace plslam
