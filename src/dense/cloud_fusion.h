// The fused dense cloud: every keyframe's cloud moved to the world by the keyframe's final
// pose and merged in a voxel grid; its semantic colours; and its two file forms.
//
//   dense_cloud.pcd            binary PCD of pcl::PointXYZRGBL: x y z in the world frame
//                              (metres), rgb the observed colour, label = class id + 1
//                              (0: no class), so unsigned labels keep "none" apart.
//   dense_cloud_semantic.ply   binary little-endian PLY: float x y z, uchar red green blue
//                              (the semantic colour below), int class (-1: none).
//
// Semantic colour: a class id k >= 0 gets the fixed palette colour HSV(hue = frac(k *
// 0.618034), s = 0.85, v = 0.95) (class 0, person, is red); a point without class keeps its
// observed colour's luminance as grey, so objects stand out on a grey scene.
//
// Stateless and thread-safe (fuseCloud locks nothing: see its comment).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/map.h"
#include "dense/dense_options.h"

namespace plslam {

/// One point of the fused cloud, world frame.
struct FusedPoint {
  Eigen::Vector3f p_w = Eigen::Vector3f::Zero();
  uint8_t r = 0, g = 0, b = 0;  ///< mean observed colour
  int16_t class_id = -1;        ///< most frequent class of the merged points (-1: none)
  int points = 1;               ///< keyframe points merged into it
};

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};
/// The palette colour of class `class_id` (>= 0); grey 128 for a negative id.
Rgb classColour(int class_id);
/// The point's semantic colour (palette for a class, grey luminance otherwise).
Rgb semanticColour(const FusedPoint& p);
Rgb semanticColour(int class_id, uint8_t r, uint8_t g, uint8_t b);

/// Called between keyframes: stage name, keyframes done, keyframes in all; returning false
/// stops the work (the result is then incomplete and flagged by the caller).
using DenseProgress = std::function<bool(const std::string& stage, size_t done, size_t total)>;

/// Keyframe `kf`'s dense cloud in the world frame (its T_w_c applied), or in the frame
/// `out` when T_out_w is given (the map frame: T_map_world).
std::vector<Eigen::Vector3f> worldPoints(const KeyFrame& kf, const SE3& T_out_w = SE3());

/// Every keyframe's cloud in the world (final T_w_c), merged with voxels of fused_voxel_m
/// (centroid, mean colour, most frequent class; voxels with fewer than min_voxel_points
/// dropped). The caller keeps others from changing `map` meanwhile (after System::finish,
/// or holding map.mutex()). `cancelled` (may be null) is set when progress stopped it.
/// With T_out_w the points are moved into that frame before the voxels (p_w then holds
/// points of that frame: the map frame, T_map_world).
std::vector<FusedPoint> fuseCloud(const Map& map, const DenseOptions& options, const DenseProgress& progress = {},
                                  bool* cancelled = nullptr, const SE3& T_out_w = SE3());

/// The cloud as binary PCD (pcl::PointXYZRGBL, see above). PCL is needed only here.
std::string cloudToPcd(const std::vector<FusedPoint>& cloud);
/// The cloud as binary little-endian PLY with semantic colours and classes (see above).
std::string cloudToSemanticPly(const std::vector<FusedPoint>& cloud);

}  // namespace plslam
