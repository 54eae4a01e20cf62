// The floor under a map, for the 2D grid. The SLAM world frame is the first keyframe's
// camera (z forward, y down, or y up when fy < 0), so "up" must be found, starting from the
// first camera's up: the top of its image, up_c = PinholeCamera::imageUp() (-y, or +y when
// fy < 0 as in ICL-NUIM):
//   ransac   planes are fitted to the lowest floor_search_fraction of the fused cloud along
//            the prior up (the floor is the lowest surface: seen from the side it is a thin
//            band, under 5 % of the cloud, but a large share of its low points) by RANSAC
//            (deterministic); among those
//            within floor_max_tilt_deg of the first camera's up that hold at least
//            floor_min_fraction of the points, the lowest along that up is the floor
//            (a table top is higher, a wall is not level). Its normal is refined by least
//            squares on the inliers among all the points. Without such a plane it falls back to gravity.
//   gravity  up is the first camera's up (the camera was held level at the start), the
//            floor height the 2nd percentile of the points' heights along it.
// With a camera-to-base transform (DenseOptions::T_base_cam) the prior up is the base's z
// at the first keyframe instead of the image's top, and since the robot stands on the floor
// a level plane more than floor_max_above_base_m above the base's origin is no candidate;
// with none left, the floor is the base's own plane (through its origin, normal its z).
// The floor frame (T_w_grid) is the map frame of core/map_frame.h (REP-103/105): z up along
// the floor normal, y = z x x (left), and with a camera-to-base transform x the base's
// forward direction laid onto the floor, origin on the floor below the base at the first
// keyframe; without one x the first camera's optical axis laid onto the floor (the top of
// its image when it looks straight down), origin on the floor below the first camera's
// centre. The grid, the clouds and the octomaps are all in it.
//
// Stateless and thread-safe.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "core/map_frame.h"
#include "core/se3.h"
#include "dense/cloud_fusion.h"
#include "dense/dense_options.h"

namespace plslam {

struct FloorPlane {
  Eigen::Vector3d up_w = Eigen::Vector3d(0, -1, 0);  ///< unit floor normal, pointing up, world frame
  double height0 = 0;        ///< up_w . p of floor points: a point's height is up_w . p - height0
  std::string method;        ///< "ransac", "gravity", "gravity (no level plane found)"; with a camera-to-base transform "base (no level plane found)" or "base (no level plane at the base)"
  int inliers = 0;           ///< ransac: points of the (subsampled) cloud on the plane
  int candidates = 0;        ///< ransac: level planes considered
  SE3 T_w_grid;              ///< the floor (map) frame above

  double height(const Eigen::Vector3d& p_w) const { return up_w.dot(p_w) - height0; }
};

/// Estimates the floor of `cloud` (world frame); T_w_c0 is the first keyframe's pose and
/// up_c its camera's up in the camera frame (PinholeCamera::imageUp()).
/// Throws ConfigError for an unknown options.floor. An empty cloud gives the gravity up
/// with the floor 1 m below the first camera's centre (so that products stay defined);
/// `method` says so.
FloorPlane estimateFloor(const std::vector<FusedPoint>& cloud, const SE3& T_w_c0, const Eigen::Vector3d& up_c,
                         const DenseOptions& options);

/// The map frame of `map` (core/map_frame.h): the floor of `cloud_w` (world frame: the
/// fused dense cloud), or of the map points when `cloud_w` is empty (a run without dense
/// clouds); `floor` (may be null) receives the floor found. `camera` is the map's camera.
/// Locks nothing: the caller keeps others from changing `map` (as for fuseCloud).
MapFrame estimateMapFrame(const Map& map, const PinholeCamera& camera, const std::vector<FusedPoint>& cloud_w,
                          const DenseOptions& options, FloorPlane* floor = nullptr);

}  // namespace plslam
