#include "frontend/frame_refinement.h"

#include "core/error.h"
#include "core/log.h"

namespace plslam {

FrameObservations matchedObservations(const FrameFeatures& f, const std::vector<Id>& point_ids,
                                      const std::vector<Id>& line_ids) {
  if (point_ids.size() != f.points.size() || line_ids.size() != f.lines.size())
    throw DataError(str("frame observations: ", point_ids.size(), " point matches for ", f.points.size(), " keypoints, ",
                        line_ids.size(), " line matches for ", f.lines.size(), " segments"));
  FrameObservations obs;
  for (size_t i = 0; i < point_ids.size(); ++i) {
    if (point_ids[i] == kNoId) continue;
    PointObs o;
    o.uv = f.points[i].uv;
    o.octave = f.points[i].octave;
    o.depth = f.points[i].depth_m;
    obs.point_index.push_back(static_cast<int>(i));
    obs.point_ids.push_back(point_ids[i]);
    obs.points.push_back(o);
  }
  for (size_t i = 0; i < line_ids.size(); ++i) {
    if (line_ids[i] == kNoId) continue;
    LineObs o;
    o.p = f.lines[i].p;
    o.q = f.lines[i].q;
    o.octave = f.lines[i].octave;
    obs.line_index.push_back(static_cast<int>(i));
    obs.line_ids.push_back(line_ids[i]);
    obs.lines.push_back(o);
  }
  return obs;
}

namespace {
// Keeps the observations for which `locate` finds the landmark (and sets its world position).
template <typename Obs, typename Locate>
void keepLocated(std::vector<int>* index, std::vector<Id>* ids, std::vector<Obs>* obs, Locate locate) {
  size_t kept = 0;
  for (size_t i = 0; i < ids->size(); ++i) {
    if (!locate((*ids)[i], &(*obs)[i])) continue;
    (*index)[kept] = (*index)[i];
    (*ids)[kept] = (*ids)[i];
    (*obs)[kept] = (*obs)[i];
    ++kept;
  }
  index->resize(kept);
  ids->resize(kept);
  obs->resize(kept);
}
}  // namespace

PoseOnlyProblem poseProblem(const Map& map, FrameObservations* obs, const SE3& T_w_c_init) {
  keepLocated(&obs->point_index, &obs->point_ids, &obs->points, [&](Id id, PointObs* o) {
    const MapPoint* p = map.point(id);
    if (p) o->p_w = p->p_w;
    return p != nullptr;
  });
  keepLocated(&obs->line_index, &obs->line_ids, &obs->lines, [&](Id id, LineObs* o) {
    const MapLine* l = map.line(id);
    if (l) o->P_w = l->P_w, o->Q_w = l->Q_w;
    return l != nullptr;
  });
  PoseOnlyProblem problem;
  problem.T_w_c_init = T_w_c_init;
  problem.points = obs->points;
  problem.lines = obs->lines;
  return problem;
}

std::optional<SE3> solveRefinement(const PinholeCamera& camera, const PoseOptimizer& optimizer,
                                   const PoseOnlyProblem& problem, int min_inliers) {
  if (static_cast<int>(problem.points.size() + problem.lines.size()) < min_inliers) return std::nullopt;
  const PoseOnlyResult r = optimizer.optimize(camera, problem);
  if (!r.converged || r.inliers < min_inliers) return std::nullopt;
  return r.T_w_c;
}

}  // namespace plslam
