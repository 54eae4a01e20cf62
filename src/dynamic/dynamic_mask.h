// The fused dynamic mask of the current frame: instance masks (with their class prior), the
// geometric check (motion_check.h) and the Delaunay regions (delaunay_motion.h) decide which
// pixels and features are dynamic.
//
// Per instance, the evidence is the features whose current pixel lies on its mask:
//   - enough of them checked (min_checked_features) and at least moving_fraction of those
//     moving (and min_moving_features)          -> dynamic, kMovingByGeometry
//   - enough checked, fewer moving              -> static,  kStillByGeometry (a seated person
//                                                   is kept; its few moving features are still rejected one by one)
//   - too few checked                           -> the class prior: kClassPrior (dynamic) for a
//                                                   potentially dynamic class, kStaticClass otherwise
// A feature's evidence is the geometric check when it has one, else the Delaunay graph's verdict.
// Delaunay regions that lie mostly outside every instance are dynamic (objects of unknown
// classes, or no segmenter) unless the geometric check finds their features still.
// The moving area found by spreading labels over all keypoints (label_spread.h), when given,
// is masked too.
//
// Stateless and thread-safe.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "dynamic/delaunay_motion.h"
#include "dynamic/instance.h"
#include "dynamic/motion_check.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindDynamicMaskOptions (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct DynamicMaskOptions {
  double moving_fraction = 0.3;
  int min_moving_features = 2;
  int min_checked_features = 3;
  bool static_classes_can_move = true;
  bool use_delaunay_evidence = true;
  double region_inside_fraction = 0.5;
  int region_min_checked = 3;
  double region_min_moving_fraction = 0.5;
  int dilate_px = 5;
  int moving_area_dilate_px = 0;
  int feature_radius_px = 0;
};

/// Binds `prefix` + "moving_fraction", "dilate_px", ...
void bindDynamicMaskOptions(OptionTable* table, const std::string& prefix, DynamicMaskOptions* options);

enum class InstanceDecisionReason {
  kMovingByGeometry,  ///< enough of its features disagree with the camera motion
  kStillByGeometry,   ///< enough features checked, too few moving
  kClassPrior,        ///< too few checked features; its class may move
  kStaticClass,       ///< too few checked features (or moving but not allowed to); its class is static
};
const char* instanceDecisionReasonName(InstanceDecisionReason reason);

struct InstanceDecision {
  int instance_id = 0;        ///< Instance::id
  int class_id = -1;          ///< Instance::class_id
  std::string class_name;     ///< Instance::class_name
  bool dynamic = false;       ///< its pixels are masked out
  InstanceDecisionReason reason = InstanceDecisionReason::kClassPrior;
  int features = 0;           ///< correspondences whose current pixel lies on the instance
  int checked = 0;            ///< of those, with motion evidence
  int moving = 0;             ///< of those, moving
};

enum class RegionDecisionReason {
  kAccepted,                ///< dynamic: a moving region outside the instances
  kInsideInstance,          ///< mostly on instances: their decisions rule
  kContradictedByGeometry,  ///< the geometric check finds its features still
};

struct RegionDecision {
  int region = -1;            ///< index into DelaunayMotionResult::regions
  bool dynamic = false;       ///< its hull is masked out
  RegionDecisionReason reason = RegionDecisionReason::kAccepted;
  int checked = 0;            ///< features with a geometric check
  int moving = 0;             ///< of those, moving
};

struct DynamicMaskStats {
  int features = 0;           ///< correspondences given
  int features_checked = 0;   ///< with motion evidence (geometric or Delaunay)
  int features_dynamic = 0;   ///< rejected (moving, or on a dynamic instance / region)
  int instances = 0;          ///< instances in the segmentation
  int instances_dynamic = 0;  ///< masked out
  int regions_dynamic = 0;    ///< Delaunay regions masked out
  int dynamic_pixels = 0;     ///< zeros in the mask
};

struct DynamicMaskResult {
  cv::Mat mask;                          ///< CV_8UC1, image size: 255 = static / usable, 0 = dynamic
  std::vector<InstanceDecision> instances;  ///< one per Segmentation instance, same order
  std::vector<RegionDecision> regions;   ///< one per Delaunay region, same order
  std::vector<uint8_t> feature_dynamic;  ///< per correspondence: 1 = do not use
  DynamicMaskStats stats;
};

/// The evidence of one frame; every part may be null (absent), the correspondences are the
/// ones motion / delaunay were computed on. The segmentation must be of the current image.
struct DynamicEvidence {
  const std::vector<MotionCorrespondence>* correspondences = nullptr;
  const MotionCheckResult* motion = nullptr;
  const DelaunayMotionResult* delaunay = nullptr;
  const Segmentation* segmentation = nullptr;
  /// Labels (as segmentation->instance_ids) that assign the features to instances; null: the
  /// segmentation's own. Carried masks give their interiors: near a carried outline a
  /// feature is as likely on the background.
  const cv::Mat* feature_labels = nullptr;
  /// Triangles of keypoints judged moving after label spreading (label_spread.h), current
  /// pixels: masked as they are, grown by moving_area_dilate_px only.
  const std::vector<std::array<cv::Point2f, 3>>* moving_triangles = nullptr;
};

/// Fuses the evidence into the dynamic mask of an image of `image_size`. Throws DataError when
/// the segmentation's label image or the per-correspondence vectors do not match.
DynamicMaskResult fuseDynamicMask(const DynamicEvidence& evidence, cv::Size image_size,
                                  const DynamicMaskOptions& options = {});

}  // namespace plslam
