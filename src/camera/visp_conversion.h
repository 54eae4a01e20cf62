// Conversion between the plslam camera model / poses and ViSP types.
#pragma once

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>

#include "camera/pinhole_camera.h"
#include "core/se3.h"

namespace plslam {

/// The ideal pinhole (perspectiveProjWithoutDistortion): what plslam's undistorted
/// feature coordinates use. When the camera has only k1, the ViSP distortion model
/// (kud = k1) is also set; ViSP cannot represent the other Brown terms.
/// Signed focal lengths carry over unchanged both ways: ViSP accepts a negative px or py
/// and its meter/pixel conversions keep the sign (what assumes a positive focal length in
/// ViSP, such as computeFov's field of view, is not used here).
vpCameraParameters toVisp(const PinholeCamera& camera);
/// Width and height are not part of vpCameraParameters. kud becomes k1.
PinholeCamera fromVisp(const vpCameraParameters& cam, int width, int height, double depth_scale);

/// T_a_b <-> ViSP aMb: the same convention, no inversion.
vpHomogeneousMatrix toVisp(const SE3& T_a_b);
SE3 fromVisp(const vpHomogeneousMatrix& aMb);

}  // namespace plslam
