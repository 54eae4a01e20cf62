// The mobile base as ViSP sees it: a unicycle (forward speed v along the base x axis, turn
// rate w about its z axis) carrying the SLAM camera. Frames (T_a_b naming, ViSP aMb):
//
//   c  the camera (optical: z forward, x right, y down), whose pose SLAM gives as T_w_c
//   b  the base, between the wheels on the floor: x forward, y left, z up (ROS base_link)
//   w  the SLAM map (the first camera frame)
//   p  the floor plane frame of the goals: z up, x/y on the floor. By default the base
//      pose at the first frame (PlanarMap::anchorAtFirstPose), as odometry starts.
//
// Poses are vpHomogeneousMatrix; camera/visp_conversion.h converts from SE3.
#pragma once

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpMatrix.h>

namespace plslam {

/// A pose on the floor: position (metres) and heading (radians, about z, from x).
struct PlanarPose {
  double x = 0, y = 0, yaw = 0;
};

/// A velocity command of the base.
struct VelocityCommand {
  double v = 0;  ///< forward speed, m/s
  double w = 0;  ///< turn rate, rad/s (positive: left)
};

/// The base's speed limits (defaults: TurtleBot3 Burger).
struct UnicycleLimits {
  double v_max = 0.22;  ///< m/s
  double w_max = 2.84;  ///< rad/s
};

/// Scales (v, w) down by one factor so that both are within the limits: the direction of
/// the command (the path's curvature v/w) is kept, as vpRobot::saturateVelocities does.
VelocityCommand saturate(const VelocityCommand& command, const UnicycleLimits& limits);

/// The unicycle's robot Jacobian eJe (6x2): (v, w) to the base twist (vpPioneer's).
vpMatrix unicycleJacobian();

/// wrap to (-pi, pi].
double wrapAngle(double a);

/// The pose of the floor-plane frame p with respect to the SLAM map w, and the camera's
/// mounting on the base.
class PlanarMap {
 public:
  /// bMc: the camera pose in the base frame. pMw: the map in the plane frame.
  explicit PlanarMap(const vpHomogeneousMatrix& bMc = defaultCameraMounting(),
                     const vpHomogeneousMatrix& pMw = vpHomogeneousMatrix())
      : bMc_(bMc), pMw_(pMw) {}
  /// The plane frame is the base at the time of the camera pose wMc0 (the first SLAM pose).
  static PlanarMap anchorAtFirstPose(const vpHomogeneousMatrix& wMc0, const vpHomogeneousMatrix& bMc);
  /// A forward-looking camera 0.10 m ahead of the wheel axis and 0.15 m above the floor,
  /// level (a Burger with a RealSense on its top plate). Measure yours.
  static vpHomogeneousMatrix defaultCameraMounting();

  /// The base pose in the plane frame from a SLAM camera pose: pMb = pMw * wMc * cMb.
  vpHomogeneousMatrix baseInPlane(const vpHomogeneousMatrix& wMc) const;
  /// The base pose in the plane frame as (x, y, yaw): translation and heading of pMb
  /// (its x axis projected on the floor).
  static PlanarPose planar(const vpHomogeneousMatrix& pMb);
  /// pMb of a planar pose.
  static vpHomogeneousMatrix toMatrix(const PlanarPose& pose);

  const vpHomogeneousMatrix& bMc() const { return bMc_; }
  const vpHomogeneousMatrix& pMw() const { return pMw_; }

 private:
  vpHomogeneousMatrix bMc_, pMw_;
};

}  // namespace plslam
