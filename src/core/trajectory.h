// A trajectory: timestamped camera poses T_w_c, sorted by time.
#pragma once

#include <vector>

#include "core/se3.h"
#include "core/time.h"

namespace plslam {

struct StampedPose {
  TimeNs t_ns = 0;
  SE3 T_w_c;
};

using Trajectory = std::vector<StampedPose>;

}  // namespace plslam
