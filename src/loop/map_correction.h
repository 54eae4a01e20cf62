// Applying a correction solved on a snapshot of the map (loop closure's pose graph and
// global BA) to the map as it is now: tracking and local mapping went on during the solve,
// so keyframes were added and local BA moved some poses and points meanwhile.
//
// Each keyframe moves by the change the solver made to its snapshot pose, left-multiplied
// onto its current pose; a keyframe made since the snapshot moves with the newest older
// snapshot keyframe (tracking went on from there); landmarks follow their keyframe, except
// points the solver estimated, which take their solved position unless local BA moved them
// since the snapshot.
//
// Stateless; the caller holds the map's mutex.
#pragma once

#include <Eigen/Core>
#include <map>
#include <utility>
#include <vector>

#include "core/map.h"
#include "core/se3.h"

namespace plslam {

/// Per keyframe of `map`, T_solved * T_snapshot^-1 of the snapshot keyframe of the same id
/// (`ids` ascending, `snapshot` and `solved` their poses); keyframes not in `ids` get the
/// change of the newest snapshot keyframe with a smaller id (identity when there is none).
std::map<Id, SE3> keyframeChanges(const Map& map, const std::vector<Id>& ids, const std::vector<SE3>& snapshot,
                                  const std::vector<SE3>& solved);

/// Moves the map by `change` (from keyframeChanges). `solved_points`: point id -> (position
/// in the snapshot, solved position). Counts a correction in the map (Map::corrections()).
void applyChanges(Map* map, const std::map<Id, SE3>& change,
                  const std::map<Id, std::pair<Eigen::Vector3d, Eigen::Vector3d>>& solved_points);

}  // namespace plslam
