#include "session/robot_frames.h"

#include <Eigen/Core>

namespace plslam {

SE3 opticalToBase() {
  Eigen::Matrix3d R_base_optical;
  // Columns: the optical axes in the base frame (x right -> -y, y down -> -z, z forward -> x).
  R_base_optical << 0, 0, 1,
                   -1, 0, 0,
                    0, -1, 0;
  return SE3(R_base_optical, Eigen::Vector3d::Zero());
}

}  // namespace plslam
