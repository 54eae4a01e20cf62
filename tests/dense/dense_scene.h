// Dense maps of the synthetic scenes for the tests: keyframe clouds from rendered frames
// placed at ground-truth poses (no SLAM), and the checks against the scene's geometry.
#pragma once

#include <vector>

#include "core/map.h"
#include "dense/cloud_fusion.h"
#include "dense/dense_options.h"
#include "dense/octree_maps.h"
#include "synth/scene.h"

namespace plslam::test {

struct GtMapOptions {
  synth::SceneKind kind = synth::SceneKind::kStatic;
  int frames = 90;          ///< scene length (30 Hz)
  int every = 10;           ///< a keyframe every this many frames
  int width = 320, height = 240;
  bool noise = true;        ///< Kinect-like depth noise
  bool reject = true;       ///< leave the moving objects' pixels out (exact masks)
  DenseOptions dense;
};

struct GtMap {
  synth::Scene scene;
  Map map;
  std::vector<TimeNs> keyframe_times;
};

/// Renders every `every`-th frame and makes its keyframe cloud at the ground-truth pose.
GtMap buildGtMap(const GtMapOptions& options);

/// Dense points farther than `static_margin` from every static surface and within
/// `tolerance` of a moving object at one of `times`: points on the persons' path (the
/// margin keeps noisy points of the floor and walls out of the count).
int pointsOnMovingPath(const synth::Scene& scene, const std::vector<Eigen::Vector3d>& points,
                       const std::vector<TimeNs>& times, double tolerance, double static_margin);

/// Fraction of `points` within `distance` of a static surface.
double fractionOnStaticSurfaces(const synth::Scene& scene, const std::vector<FusedPoint>& points, double distance);

/// The centres of the occupied voxels at the tree's resolution (pruned leaves expanded).
std::vector<Eigen::Vector3d> occupiedVoxelCentres(const octomap::OcTree& tree);

}  // namespace plslam::test
