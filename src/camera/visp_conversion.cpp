#include "camera/visp_conversion.h"

namespace plslam {

vpCameraParameters toVisp(const PinholeCamera& c) {
  const bool only_k1 = c.dist[0] != 0 && c.dist[1] == 0 && c.dist[2] == 0 && c.dist[3] == 0 && c.dist[4] == 0;
  if (only_k1) {
    // kdu (distorted -> ideal) to first order is -kud.
    return vpCameraParameters(c.fx, c.fy, c.cx, c.cy, c.dist[0], -c.dist[0]);
  }
  return vpCameraParameters(c.fx, c.fy, c.cx, c.cy);
}

PinholeCamera fromVisp(const vpCameraParameters& cam, int width, int height, double depth_scale) {
  PinholeCamera c;
  c.name = "visp";
  c.width = width;
  c.height = height;
  c.fx = cam.get_px();
  c.fy = cam.get_py();
  c.cx = cam.get_u0();
  c.cy = cam.get_v0();
  if (cam.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion) c.dist[0] = cam.get_kud();
  c.depth_scale = depth_scale;
  return c;
}

vpHomogeneousMatrix toVisp(const SE3& T) {
  vpHomogeneousMatrix M;
  const Eigen::Matrix4d m = T.matrix();
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned k = 0; k < 4; ++k) M[r][k] = m(r, k);
  return M;
}

SE3 fromVisp(const vpHomogeneousMatrix& M) {
  Eigen::Matrix4d m;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned k = 0; k < 4; ++k) m(r, k) = M[r][k];
  return SE3(m);
}

}  // namespace plslam
