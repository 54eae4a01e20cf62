// A frame's matched observations and the pose-only problem built from them: the tracker
// builds its problems this way, and so does the re-estimation of a tracked frame's pose
// once the map around it has settled.
//
// A frame is tracked against landmarks as they are at that moment: the newest keyframe's
// points come straight from one depth image, before local BA has seen them. The frame keeps
// its inlier observations (which landmark each keypoint and segment matched); once local BA
// has refined those landmarks (its reference keyframe is some keyframes old, or the run has
// ended), its pose is optimised again against their current positions, starting from where
// it was, with the tracker's robust pose-only optimiser. Landmarks culled since are left
// out. It lowered the ATE on fr3_sitting_static_150 with YOLO masks (docs/RESULTS.md, "Frame
// refinement"); the poses published while tracking are not changed.
//
// Stateless.
#pragma once

#include <optional>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/map.h"
#include "optim/pose_optimizer.h"

namespace plslam {

/// A frame's matches: the keypoint / segment and the landmark of each observation, and what
/// was seen (the world positions in `points` / `lines` are filled in by poseProblem).
struct FrameObservations {
  std::vector<int> point_index;  ///< the keypoint of each point observation
  std::vector<Id> point_ids;
  std::vector<PointObs> points;
  std::vector<int> line_index;   ///< the segment of each line observation
  std::vector<Id> line_ids;
  std::vector<LineObs> lines;
  bool empty() const { return point_ids.empty() && line_ids.empty(); }
};

/// The observations of `f` whose keypoint / segment matched a landmark (`point_ids` per
/// keypoint, `line_ids` per segment, kNoId: none). Throws DataError when the sizes differ.
FrameObservations matchedObservations(const FrameFeatures& f, const std::vector<Id>& point_ids,
                                      const std::vector<Id>& line_ids);

/// The pose-only problem of the observations `obs` against the landmarks of `map` as they
/// are now, starting from `T_w_c_init`. Observations whose landmark is gone (culled) are
/// dropped from `obs`, so that problem.points[k] is obs->points[k] (lines alike). The caller
/// holds map.mutex(); the solve needs no lock.
PoseOnlyProblem poseProblem(const Map& map, FrameObservations* obs, const SE3& T_w_c_init);

/// The solution of `problem`; none when fewer than `min_inliers` observations remain inliers
/// or the optimiser fails (the frame keeps its tracked pose).
std::optional<SE3> solveRefinement(const PinholeCamera& camera, const PoseOptimizer& optimizer,
                                   const PoseOnlyProblem& problem, int min_inliers);

}  // namespace plslam
