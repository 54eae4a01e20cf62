// Moving keypoints found without a match: the free-space test against an earlier depth image.
//
// The motion check can only judge a keypoint it matched in the earlier frame, and near walkers
// move farther than its search radius (docs/RESULTS.md, "Why geometry alone fails in the
// crowd"). The earlier depth image needs no match. A static point seen now was there then:
// moved into the earlier camera by the camera motion, it lies on the surface that frame saw
// along its ray, or behind it (something nearer hid it then). So a point that lands clearly in
// front of everything the earlier frame saw around that pixel occupies space that frame saw
// empty: it has arrived there since, so it moves. The opposite case (behind what was seen) is
// a disocclusion or a departure, which this test cannot tell apart: it gives no verdict.
//
// The test is one-sided on purpose. A keypoint on an object's outline projects, with a slightly
// wrong motion, onto the far surface beside it; taking the nearest depth in a window around
// the projection keeps such keypoints still, as only a point in front of the whole window
// counts.
//
// Stateless and thread-safe.
#pragma once

#include <string>
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "core/se3.h"
#include "dynamic/motion_check.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindFreeSpaceOptions (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct FreeSpaceOptions {
  bool enabled = false;
  int window_radius_px = 3;   ///< the earlier depth is the nearest within this many pixels of the projection
  double sigmas = 4.0;        ///< the point must be this many depth-noise sigmas in front of it
  double min_gap_m = 0.05;    ///< and at least this far (depth quantisation, motion error)
  double min_valid_fraction = 0.5;  ///< of the window's pixels with depth, or no verdict
};

/// Binds `prefix` + "enabled", "window_radius_px", "sigmas", "min_gap_m", "min_valid_fraction".
void bindFreeSpaceOptions(OptionTable* table, const std::string& prefix, FreeSpaceOptions* options);

/// Per point of the current camera frame (`points_cur`, NaN where there is no depth): 1 when it
/// lies in space the earlier frame saw empty, else 0 (no verdict: still, occluded then, outside
/// the earlier image, or no depth there). `T_earlier_cur` moves current-frame points into the
/// earlier camera; `earlier_depth_m` is that frame's depth image (CV_32FC1, metres, NaN for
/// none, raw pixels: `camera` distorts the projections into it). Throws DataError for a depth
/// image of another type or size than the camera's.
std::vector<uint8_t> pointsInEarlierFreeSpace(const std::vector<Eigen::Vector3d>& points_cur, const SE3& T_earlier_cur,
                                              const cv::Mat& earlier_depth_m, const PinholeCamera& camera,
                                              const PointNoiseOptions& noise, const FreeSpaceOptions& options = {});

}  // namespace plslam
