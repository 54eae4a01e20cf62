// The semantic side of a frame's segmentation, in the form the map keeps: a per-pixel class
// image (for the dense cloud) and the instances with their 3D centroids (for loop closure).
//
// Stateless and thread-safe.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "dynamic/dynamic_mask.h"
#include "dynamic/instance.h"

namespace plslam {

/// CV_16SC1 of the label image's size: the class id of the instance at each pixel, -1 where
/// there is none. Empty when the segmentation is.
cv::Mat classImage(const Segmentation& segmentation);

/// One KeyframeInstance per instance of `segmentation`: class, box, area, whether
/// `decisions` (fuseDynamicMask's, same order; may be empty: none dynamic) masked it out,
/// and the median 3D point of its pixels with depth (CV_32F metres, NaN invalid; may be
/// empty) in the camera frame.
std::vector<KeyframeInstance> describeInstances(const Segmentation& segmentation,
                                                const std::vector<InstanceDecision>& decisions,
                                                const cv::Mat& depth_m, const PinholeCamera& camera);

}  // namespace plslam
