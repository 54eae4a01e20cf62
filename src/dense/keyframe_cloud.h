// The dense cloud of one keyframe: its depth pixels back-projected into the camera frame,
// with their colour and semantic class, moving objects left out, downsampled.
//
// Stateless and thread-safe.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "dense/dense_options.h"

namespace plslam {

/// Camera-frame points of a keyframe. Inputs are of the camera's size:
///   bgr           CV_8UC3 colour (empty: points are grey 128)
///   depth_m       CV_32FC1 metres, NaN = no reading (registered to the colour image)
///   dynamic_mask  CV_8UC1, 0 = moving objects, left out (empty: none)
///   class_image   CV_16SC1 class id per pixel, -1 = none (dynamic/semantic_labels.h
///                 classImage(); empty: every point has class -1)
/// Every `pixel_stride`-th pixel with depth in [min_depth_m, max_depth_m] and no depth jump
/// to a neighbour is kept, its depth denoised (smooth_radius_px: mean inverse depth of the
/// window's pixels within 3 sigma of it, sigma = depth_sigma_coeff z^2) and back-projected
/// through the distortion; then, with keyframe_voxel_m > 0, one point per voxel (centroid,
/// mean colour, most frequent class). Throws DataError on an image of another type or size.
std::vector<DensePoint> makeKeyframeCloud(const PinholeCamera& camera, const cv::Mat& bgr, const cv::Mat& depth_m,
                                          const cv::Mat& dynamic_mask, const cv::Mat& class_image,
                                          const DenseOptions& options);

}  // namespace plslam
