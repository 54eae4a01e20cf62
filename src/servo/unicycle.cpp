#include "servo/unicycle.h"

#include <visp3/core/vpRotationMatrix.h>
#include <visp3/core/vpTranslationVector.h>
#include <visp3/robot/vpRobot.h>

#include <algorithm>
#include <cmath>

namespace plslam {

VelocityCommand saturate(const VelocityCommand& command, const UnicycleLimits& limits) {
  vpColVector in(2), max(2);
  in[0] = command.v;
  in[1] = command.w;
  max[0] = limits.v_max;
  max[1] = limits.w_max;
  const vpColVector out = vpRobot::saturateVelocities(in, max, false);
  // The scaling can overshoot a limit by an ulp; clamp so that |v| <= v_max holds exactly.
  return {std::clamp(out[0], -limits.v_max, limits.v_max), std::clamp(out[1], -limits.w_max, limits.w_max)};
}

vpMatrix unicycleJacobian() {
  vpMatrix eJe(6, 2, 0.0);
  eJe[0][0] = 1;  // v along the base x axis
  eJe[5][1] = 1;  // w about the base z axis
  return eJe;
}

double wrapAngle(double a) {
  a = std::remainder(a, 2 * M_PI);
  return a <= -M_PI ? a + 2 * M_PI : a;
}

PlanarMap PlanarMap::anchorAtFirstPose(const vpHomogeneousMatrix& wMc0, const vpHomogeneousMatrix& bMc) {
  return PlanarMap(bMc, (wMc0 * bMc.inverse()).inverse());
}

vpHomogeneousMatrix PlanarMap::defaultCameraMounting() {
  // Columns: the camera axes in the base frame (x_c = -y_b, y_c = -z_b, z_c = x_b).
  vpRotationMatrix bRc;
  bRc[0][0] = 0, bRc[0][1] = 0, bRc[0][2] = 1;
  bRc[1][0] = -1, bRc[1][1] = 0, bRc[1][2] = 0;
  bRc[2][0] = 0, bRc[2][1] = -1, bRc[2][2] = 0;
  return vpHomogeneousMatrix(vpTranslationVector(0.10, 0.0, 0.15), bRc);
}

vpHomogeneousMatrix PlanarMap::baseInPlane(const vpHomogeneousMatrix& wMc) const {
  return pMw_ * wMc * bMc_.inverse();
}

PlanarPose PlanarMap::planar(const vpHomogeneousMatrix& pMb) {
  return {pMb[0][3], pMb[1][3], std::atan2(pMb[1][0], pMb[0][0])};
}

vpHomogeneousMatrix PlanarMap::toMatrix(const PlanarPose& pose) {
  return vpHomogeneousMatrix(vpTranslationVector(pose.x, pose.y, 0.0), vpRotationMatrix(0.0, 0.0, pose.yaw));
}

}  // namespace plslam
