#include "frontend/frame_refinement.h"

#include "core/error.h"
#include "core/log.h"

namespace plslam {

FrameObservations inlierObservations(const FrameFeatures& f, const std::vector<Id>& point_ids,
                                     const std::vector<Id>& line_ids) {
  if (point_ids.size() != f.points.size() || line_ids.size() != f.lines.size())
    throw DataError(str("frame refinement: ", point_ids.size(), " point matches for ", f.points.size(), " keypoints, ",
                        line_ids.size(), " line matches for ", f.lines.size(), " segments"));
  FrameObservations obs;
  for (size_t i = 0; i < point_ids.size(); ++i) {
    if (point_ids[i] == kNoId) continue;
    PointObs o;
    o.uv = f.points[i].uv;
    o.octave = f.points[i].octave;
    o.depth = f.points[i].depth_m;
    obs.point_ids.push_back(point_ids[i]);
    obs.points.push_back(o);
  }
  for (size_t i = 0; i < line_ids.size(); ++i) {
    if (line_ids[i] == kNoId) continue;
    LineObs o;
    o.p = f.lines[i].p;
    o.q = f.lines[i].q;
    o.octave = f.lines[i].octave;
    obs.line_ids.push_back(line_ids[i]);
    obs.lines.push_back(o);
  }
  return obs;
}

PoseOnlyProblem refinementProblem(const Map& map, const FrameObservations& obs, const SE3& T_w_c_init) {
  PoseOnlyProblem problem;
  problem.T_w_c_init = T_w_c_init;
  for (size_t i = 0; i < obs.point_ids.size(); ++i)
    if (const MapPoint* p = map.point(obs.point_ids[i])) {
      problem.points.push_back(obs.points[i]);
      problem.points.back().p_w = p->p_w;
    }
  for (size_t i = 0; i < obs.line_ids.size(); ++i)
    if (const MapLine* l = map.line(obs.line_ids[i])) {
      problem.lines.push_back(obs.lines[i]);
      problem.lines.back().P_w = l->P_w;
      problem.lines.back().Q_w = l->Q_w;
    }
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
