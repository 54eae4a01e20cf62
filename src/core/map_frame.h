// The map frame every world-frame output is written in (REP-103/105, "map"): z up along
// the floor normal, y left, and
//   - with a camera-to-base transform (calibration.camera_to_base, `plslam calib base`):
//     x the base's forward direction at the first keyframe laid onto the floor, origin on
//     the floor below the base's origin (origin: base);
//   - without one: x the first camera's optical axis laid onto the floor, origin on the
//     floor below the first camera's centre (origin: camera). The SLAM world frame
// ("world": the first keyframe's camera, z forward, y down) stays the frame of
// trajectory.txt and of the map file's poses, so evaluation against TUM ground truth is
// unchanged; T_map_world converts between the two (p_map = T_map_world * p_world).
//
// map_frame.yaml, written beside the outputs and stored in the map file:
//
//   # ...comments...
//   format: plslam_map_frame 1
//   parent_frame: map
//   child_frame: world
//   translation: [tx, ty, tz]        # metres: the world origin (first camera) in the map
//   rotation: [qx, qy, qz, qw]       # unit quaternion of R_map_world
//   camera_height_m: 0.8             # the first camera's centre above the floor
//   floor_method: ransac             # how up and the floor were found (dense/floor_plane.h)
//   floor_source: dense              # the points it was found in: dense (fused cloud) or sparse (map points)
//   floor_points: 1234               # ransac: points on the floor plane
//   origin: base                     # below what the origin is: base (the robot's, at the first keyframe) or camera
//
// translation + rotation define the transform; the rest says how it was found.
#pragma once

#include <string>

#include "core/se3.h"

namespace plslam {

/// File name of the map frame beside the outputs.
inline constexpr char kMapFrameYaml[] = "map_frame.yaml";

struct MapFrame {
  SE3 T_map_world;             ///< p_map = T_map_world * p_world
  std::string floor_method;    ///< "ransac", "gravity", ... (FloorPlane::method)
  std::string floor_source;    ///< "dense" or "sparse"
  int floor_points = 0;        ///< ransac: inliers of the floor plane
  std::string origin = "camera";  ///< "base": below the base at the first keyframe, x its forward; "camera": below the first camera

  /// The first camera's centre (the world origin) above the floor, metres.
  double cameraHeight() const { return T_map_world.translation().z(); }
};

/// The YAML document above.
std::string mapFrameToYaml(const MapFrame& frame);
/// Parses it. Throws IoError naming `source` and the key when a required key (format,
/// translation, rotation) is missing or malformed, or the quaternion is not unit length.
MapFrame parseMapFrameYaml(const std::string& text, const std::string& source);

}  // namespace plslam
