// Motion labels spread over a Delaunay graph of all the current frame's features.
//
// The geometric check can only judge a feature that was matched in the compared frame; on a
// walking person most keypoints are not (limbs swing, the view of the body changes), and in the
// synthetic dynamic scene nearly every missed person keypoint was an unmatched one. A feature
// lies on the same object as its Delaunay neighbours at about its depth, so:
//
//  1. the features with depth are triangulated at their current pixels; an edge counts when
//     it joins one surface (SameSurfaceOptions) and is at most max_edge_px long (edges to a
//     farther wall, or across the image, do not);
//  2. an isolated "moving" feature (no moving neighbour, at least min_still_neighbours still
//     ones) is a mismatch, not a moving object: it becomes still (it stays usable for tracking);
//  3. unjudged features take the majority label of their judged neighbours, over `passes`
//     rounds (so labels reach a few edges into an unmatched patch), ties left unjudged;
//  4. the triangles whose three corners end up moving, joined by counted edges, are the
//     moving area (for the pixel mask: lines and dense points on it are dropped too).
//
// Stateless and thread-safe.
#pragma once

#include <string>
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "dynamic/delaunay_graph.h"
#include "dynamic/delaunay_motion.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindLabelSpreadOptions (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct LabelSpreadOptions {
  SameSurfaceOptions surface;      ///< which edges join one surface
  double max_edge_px = 60.0;
  int min_still_neighbours = 1;
  int passes = 10;
};

/// Binds `prefix` + "passes", "max_edge_px", "min_still_neighbours", "min_step_m", "step_ratio".
void bindLabelSpreadOptions(OptionTable* table, const std::string& prefix, LabelSpreadOptions* options);

/// Step 1: the features' same-surface graph. Built once a frame, shared by the flood and the
/// spreading (triangulating costs about as much as either).
struct SurfaceGraph {
  DelaunayGraph graph;                       ///< over the features with depth inside the image
  std::vector<std::vector<int>> neighbours;  ///< per feature, its counted edges' other ends, sorted
};

/// `uv`: current ideal pixels; `depth_m`: their depths (NaN: none, not in the graph). Throws
/// DataError when the sizes differ.
SurfaceGraph buildSurfaceGraph(const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& depth_m,
                               cv::Size image_size, const LabelSpreadOptions& options = {});

struct LabelSpreadResult {
  std::vector<int8_t> labels;  ///< per feature: -1 unjudged, 0 still, 1 moving
  int isolated_cleared = 0;    ///< moving features turned still (step 2)
  int spread_moving = 0;       ///< unjudged features labelled moving (step 3)
  int spread_still = 0;        ///< unjudged features labelled still (step 3)
  std::vector<std::array<cv::Point2f, 3>> moving_triangles;  ///< step 4, current pixels
};

/// Steps 2-4 on `graph`; `labels`: -1 unjudged, 0 still, 1 moving (features without depth are
/// left as they are). Throws DataError when the sizes differ.
LabelSpreadResult spreadMotionLabels(const SurfaceGraph& graph, const std::vector<int8_t>& labels,
                                     const LabelSpreadOptions& options = {});

/// From the `seeds` (features labelled moving), every unjudged feature (-1 in `labels`) joined
/// to a moving one by a counted edge of `graph` becomes moving, and so on: a flood, not a vote,
/// so that a near walker's whole body follows its flagged outline whatever still neighbours it
/// has. Judged features are left as they are. Returns how many it labelled. Throws DataError
/// when the sizes differ.
int floodMovingLabels(const SurfaceGraph& graph, std::vector<int> seeds, std::vector<int8_t>* labels);

}  // namespace plslam
