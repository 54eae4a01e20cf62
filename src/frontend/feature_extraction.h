// From an RGB-D frame to the features the tracker uses: ORB keypoints and LSD/LBD line
// segments (on two threads), moved to ideal pixels, keypoints given their depth.
#pragma once

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/map.h"
#include "core/option_table.h"
#include "features/line_extractor.h"
#include "features/orb_extractor.h"

namespace plslam {

struct FeatureOptions {
  OrbOptions orb;        ///< keypoints
  LineOptions lines;     ///< line segments
  bool use_lines = true; ///< extract line segments at all
  bool parallel = true;  ///< points and lines on two threads (the result does not depend on it)
  double min_depth_m = 0.1;  ///< depth readings below this count as none
};

void bindFeatureOptions(OptionTable* table, FeatureOptions* options);

/// `mask` (CV_8U, 0 = forbidden; may be empty) keeps features off those pixels.
FrameFeatures extractFeatures(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera,
                              const FeatureOptions& options);

}  // namespace plslam
