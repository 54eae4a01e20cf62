// Dense maps of the synthetic scenes for the tests: keyframe clouds from rendered frames
// placed at ground-truth poses (no SLAM), and the checks against the scene's geometry.
#pragma once

#include <string>
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
  bool first_camera_world = false;  ///< poses in the first camera's frame, as SLAM gives them (not the scene's)
  DenseOptions dense;
};

struct GtMap {
  synth::Scene scene;
  Map map;
  std::vector<TimeNs> keyframe_times;
  SE3 T_scene_world;        ///< the map's world frame in the scene (the first camera's true pose, or identity)
};

/// Renders every `every`-th frame and makes its keyframe cloud at the ground-truth pose.
GtMap buildGtMap(const GtMapOptions& options);

/// A small map whose products carry a class: the dynamic scene with its persons kept in
/// (no rejection), 60 frames, a keyframe every 12, 2 cm fused voxels, a 0.1 m octree.
inline GtMapOptions personsKeptMapOptions() {
  GtMapOptions o;
  o.kind = synth::SceneKind::kDynamic;
  o.frames = 60;
  o.every = 12;
  o.reject = false;
  o.dense.fused_voxel_m = 0.02;
  o.dense.octree_resolution_m = 0.1;
  return o;
}

/// Dense points farther than `static_margin` from every static surface and within
/// `tolerance` of a moving object at one of `times`: points on the persons' path (the
/// margin keeps noisy points of the floor and walls out of the count).
int pointsOnMovingPath(const synth::Scene& scene, const std::vector<Eigen::Vector3d>& points,
                       const std::vector<TimeNs>& times, double tolerance, double static_margin);

/// Fraction of `points` within `distance` of a static surface.
double fractionOnStaticSurfaces(const synth::Scene& scene, const std::vector<FusedPoint>& points, double distance);

/// The centres of the occupied voxels at the tree's resolution (pruned leaves expanded).
std::vector<Eigen::Vector3d> occupiedVoxelCentres(const octomap::OcTree& tree);

/// The true map frame (core/map_frame.h) of a scene seen first from T_scene_c0: z up (the
/// scene's), x the first camera's optical axis laid onto the floor, origin on the floor
/// (z = 0) below it. Returns T_scene_map.
SE3 trueMapFrame(const SE3& T_scene_c0);

/// An estimated map frame and a map-frame octree against the scene's truth.
struct MapFrameCheck {
  double rotation_error_deg = 0;  ///< angle of R_map_world (estimated) against the truth
  double up_error_deg = 0;        ///< angle between the estimated and the true up
  double camera_height_m = 0, true_camera_height_m = 0;  ///< the first camera above the floor
  int floor_voxels = 0;           ///< occupied voxels on the true floor (away from walls and furniture)
  double floor_mean_z = 0;        ///< their mean map-frame z (m; the floor is at z = 0)
  double floor_p95_abs_z = 0;     ///< 95th percentile of |z| (m)
  struct Face {
    std::string name;             ///< box name and face ("room -y": the room's wall at -y)
    int voxels = 0;
    double tilt_deg = 0;          ///< angle of the plane fitted to its voxels (map frame) to the vertical
  };
  std::vector<Face> faces;        ///< vertical faces (room walls, furniture sides) with 100 voxels or more
  double max_wall_tilt_deg = 0;   ///< the largest tilt of them
  std::string facesText() const;  ///< "name: voxels, tilt" per face, for the test output
};
/// Voxels are put in the scene through the estimate (T_scene_world * T_map_world^-1) to pick
/// the floor's and the walls' with the truth; their map-frame coordinates are then checked.
MapFrameCheck checkMapFrame(const synth::Scene& scene, const SE3& T_scene_world, const SE3& T_map_world,
                            const octomap::OcTree& tree);

}  // namespace plslam::test
