// Motion evidence from a Delaunay graph of the features (no segmentation needed, so it finds
// objects of any class): the correspondences with depth in both frames are triangulated at
// their current pixels (cv::Subdiv2D). Rigid scenery keeps the 3D length of every edge; an
// edge that joins a moving object to the background usually does not.
//
//  1. Camera motion: the geometric check's result (given, or run here).
//  2. Edge test: an edge is broken when its 3D length change exceeds the noise of the two
//     lengths (the point covariances of motion_check.h, chi2 with 1 dof).
//  3. Moving features: with a camera motion, the check's flags. Without one (kNoReference, a
//     weak fallback), the features outside the largest group joined by rigid triangles (three
//     kept edges), or any group holding static_group_fraction of the features. "Most incident
//     edges broken" alone would only catch isolated points: inside an object most edges join
//     it to itself. Edge lengths are the weaker evidence: an object crossing the view in front
//     of a farther wall changes the lengths of its edges to the wall very little (they point
//     along the depth, where the noise is largest); in the tests a third to a half of such
//     edges stay within the noise, and a few kept ones join the object to the background.
//  4. Regions: moving features joined by kept edges on one surface (they move rigidly
//     together), with the Delaunay triangles they cover and their convex hull.
//
// Stateless and thread-safe.
#pragma once

#include <string>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/se3.h"
#include "dynamic/motion_check.h"

namespace plslam {

class OptionTable;

/// When a graph edge joins one surface: its two depths differ by at most
/// max(min_step_m, ratio * the nearer depth). Edges from a person to the wall behind do not.
/// Configuration keys: each field's key, doc string and range are where it is bound, in bindSurface
/// (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct SameSurfaceOptions {
  double min_step_m = 0.20;
  double ratio = 0.05;
  bool joins(double z_a, double z_b) const { return std::abs(z_a - z_b) <= std::max(min_step_m, ratio * std::min(z_a, z_b)); }
};

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindDelaunayMotionOptions (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct DelaunayMotionOptions {
  MotionCheckOptions motion;       ///< noise model of the edge test; the geometric check when none is given
  double chi2_length = 10.83;
  double static_group_fraction = 0.3;
  int min_region_features = 3;
  SameSurfaceOptions region_surface;  ///< regions grow only over edges that join one surface
};

/// Binds `prefix` + "chi2_length", ...; not `motion`: the dynamic filter gives the graph its own check's options.
void bindDelaunayMotionOptions(OptionTable* table, const std::string& prefix, DelaunayMotionOptions* options);

enum class DelaunayStatus {
  kOk,             ///< graph built, camera motion available
  kTooFewPoints,   ///< fewer than 3 correspondences with depth inside the image: no graph
  kNoReference,    ///< no camera motion (the check failed): moving = cut off by broken edges (length test only)
};
const char* delaunayStatusName(DelaunayStatus status);

/// One edge of the triangulation between correspondences a < b.
struct DelaunayEdge {
  int a = -1, b = -1;        ///< correspondence indices
  double length_prev = 0;    ///< 3D length in the previous frame, metres
  double length_cur = 0;     ///< 3D length in the current frame, metres
  double sigma = 0;          ///< standard deviation of the length change, metres
  bool broken = false;       ///< the length changed beyond the noise
};

/// A group of moving features found by the graph.
struct MovingRegion {
  std::vector<int> features;        ///< correspondence indices
  std::vector<cv::Point2f> hull;    ///< convex hull of their current pixels (image coordinates)
  /// The Delaunay triangles with all three corners in the region: the area it covers (tighter
  /// than the hull, which also spans the background between a walker's legs).
  std::vector<std::array<cv::Point2f, 3>> triangles;
};

struct DelaunayMotionResult {
  DelaunayStatus status = DelaunayStatus::kTooFewPoints;
  std::vector<DelaunayEdge> edges;
  std::vector<uint8_t> in_graph;        ///< per correspondence: a vertex of the triangulation
  std::vector<uint8_t> moving;          ///< per correspondence: judged moving by the graph
  std::vector<float> broken_fraction;   ///< per correspondence: broken / incident edges (NaN outside the graph)
  std::optional<SE3> reference;         ///< the camera motion T_cur_prev the features were judged by
  bool reference_given = false;         ///< it came from the caller's check (else from checkMotion here)
  std::vector<MovingRegion> regions;    ///< moving regions of at least min_region_features

  int brokenCount() const;
  int movingCount() const;
};

/// Builds the graph over the correspondences with depth in both frames (current pixels inside
/// the camera's image) and finds the moving features and regions. `motion`: the geometric
/// check of the same correspondences (checkMotion is run here when null; when it is given but
/// failed, the graph works without a camera motion). Throws DataError when its size differs.
DelaunayMotionResult analyseDelaunayMotion(const std::vector<MotionCorrespondence>& correspondences,
                                           const PinholeCamera& camera, const DelaunayMotionOptions& options = {},
                                           const MotionCheckResult* motion = nullptr);

}  // namespace plslam
