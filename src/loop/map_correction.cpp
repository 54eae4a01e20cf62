#include "loop/map_correction.h"

namespace plslam {

std::map<Id, SE3> keyframeChanges(const Map& map, const std::vector<Id>& ids, const std::vector<SE3>& snapshot,
                                  const std::vector<SE3>& solved) {
  std::map<Id, SE3> change;
  for (size_t i = 0; i < ids.size(); ++i) change[ids[i]] = solved[i] * snapshot[i].inverse();
  SE3 newest;
  for (const auto& [id, kf] : map.keyframes()) {
    const auto it = change.find(id);
    if (it != change.end()) newest = it->second;
    else change[id] = newest;
  }
  return change;
}

namespace {

/// The change of a landmark's keyframe: its first keyframe's, else any observer's.
const SE3* landmarkChange(const std::map<Id, SE3>& change, Id first, const std::map<Id, int>& observations) {
  auto it = change.find(first);
  if (it != change.end()) return &it->second;
  for (const auto& [kf, idx] : observations)
    if ((it = change.find(kf)) != change.end()) return &it->second;
  return nullptr;
}

}  // namespace

void applyChanges(Map* map, const std::map<Id, SE3>& change,
                  const std::map<Id, std::pair<Eigen::Vector3d, Eigen::Vector3d>>& solved_points) {
  for (const auto& [id, T] : change)
    if (KeyFrame* kf = map->keyframe(id)) kf->T_w_c = T * kf->T_w_c;
  for (const auto& [pid, p] : map->points()) {
    MapPoint* mp = map->point(pid);
    const auto s = solved_points.find(pid);
    if (s != solved_points.end() && s->second.first == mp->p_w) mp->p_w = s->second.second;
    else if (const SE3* T = landmarkChange(change, p.first_keyframe, p.observations)) mp->p_w = *T * mp->p_w;
  }
  for (const auto& [lid, l] : map->lines()) {
    MapLine* ml = map->line(lid);
    if (const SE3* T = landmarkChange(change, l.first_keyframe, l.observations)) {
      ml->P_w = *T * ml->P_w;
      ml->Q_w = *T * ml->Q_w;
    }
  }
  map->noteCorrection();
}

}  // namespace plslam
