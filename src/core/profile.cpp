#include "core/profile.h"

namespace plslam {

const char* stageName(Stage s) {
  switch (s) {
    case Stage::kOrbDetect: return "orb_detect";
    case Stage::kOrbDescribe: return "orb_describe";
    case Stage::kLsd: return "lsd";
    case Stage::kLineMerge: return "line_merge";
    case Stage::kLbd: return "lbd";
    case Stage::kUndistort: return "undistort";
    case Stage::kDynamic: return "dynamic";
    case Stage::kSearch: return "search";
    case Stage::kPoseOptimisation: return "pose_optimisation";
    case Stage::kKeyframe: return "keyframe";
  }
  return "unknown";
}

}  // namespace plslam
