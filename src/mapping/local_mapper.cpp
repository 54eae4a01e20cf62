#include "mapping/local_mapper.h"

#include <algorithm>
#include <map>
#include <set>

#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"

namespace plslam {

namespace {
const Logger kLog("mapping");

/// A local bundle-adjustment problem and the map ids of its keyframes, points and lines
/// (indexed as in the problem).
struct LocalWindow {
  BundleProblem problem;
  std::vector<Id> kf_ids, point_ids, line_ids;
  std::map<Id, int> kf_index;
};

/// The free keyframes (`keyframe` and its best covisible ones) and every landmark they observe.
void addFreeKeyframesAndLandmarks(Map* map, Id keyframe, const LocalMapperOptions& options, LocalWindow* w) {
  BundleProblem& problem = w->problem;
  std::vector<Id> free_kfs{keyframe};
  for (const auto& [id, shared] : map->covisible(keyframe, options.min_covisible_points)) {
    if (static_cast<int>(free_kfs.size()) >= options.ba_keyframes) break;
    free_kfs.push_back(id);
  }
  std::map<Id, int> pt_index, ln_index;
  for (Id id : free_kfs) {
    w->kf_index[id] = static_cast<int>(problem.keyframes.size());
    w->kf_ids.push_back(id);
    problem.keyframes.push_back({map->keyframe(id)->T_w_c, false});
  }
  // The first keyframe anchors the world frame.
  if (w->kf_index.count(map->keyframes().begin()->first))
    problem.keyframes[w->kf_index[map->keyframes().begin()->first]].fixed = true;
  for (Id id : free_kfs) {
    const KeyFrame* kf = map->keyframe(id);
    for (Id p : kf->point_ids)
      if (p != kNoId && !pt_index.count(p)) {
        pt_index[p] = static_cast<int>(problem.points.size());
        w->point_ids.push_back(p);
        problem.points.push_back({map->point(p)->p_w, false});
      }
    if (options.use_lines)
      for (Id l : kf->line_ids)
        if (l != kNoId && !ln_index.count(l)) {
          ln_index[l] = static_cast<int>(problem.lines.size());
          w->line_ids.push_back(l);
          const MapLine* ml = map->line(l);
          problem.lines.push_back({ml->P_w, ml->Q_w, false});
        }
  }
}

/// The problem index of keyframe `id`; a keyframe outside the window joins it as a fixed one
/// while there are fewer than ba_fixed_keyframes + 1 fixed ones, else -1 (its observations are left out).
int windowKeyframeIndex(Map* map, Id id, const LocalMapperOptions& options, LocalWindow* w) {
  auto it = w->kf_index.find(id);
  if (it != w->kf_index.end()) return it->second;
  int fixed = 0;
  for (const auto& k : w->problem.keyframes) fixed += k.fixed;
  if (fixed >= options.ba_fixed_keyframes + 1) return -1;
  w->kf_index[id] = static_cast<int>(w->problem.keyframes.size());
  w->kf_ids.push_back(id);
  w->problem.keyframes.push_back({map->keyframe(id)->T_w_c, true});
  return w->kf_index[id];
}

/// Every observation of the window's landmarks (from keyframes in the window or joining it).
void addObservations(Map* map, const LocalMapperOptions& options, LocalWindow* w) {
  for (size_t i = 0; i < w->point_ids.size(); ++i) {
    for (const auto& [kf, idx] : map->point(w->point_ids[i])->observations) {
      const int k = windowKeyframeIndex(map, kf, options, w);
      if (k < 0) continue;
      const Keypoint& kp = map->keyframe(kf)->features.points[idx];
      w->problem.point_obs.push_back({k, static_cast<int>(i), kp.uv, kp.octave, kp.depth_m});
    }
  }
  for (size_t i = 0; i < w->line_ids.size(); ++i) {
    for (const auto& [kf, idx] : map->line(w->line_ids[i])->observations) {
      const int k = windowKeyframeIndex(map, kf, options, w);
      if (k < 0) continue;
      const Segment2D& s = map->keyframe(kf)->features.lines[idx];
      w->problem.line_obs.push_back({k, static_cast<int>(i), s.p, s.q, s.octave});
    }
  }
}

/// The local window around `keyframe`; call with the map locked.
LocalWindow gatherLocalWindow(Map* map, Id keyframe, const LocalMapperOptions& options) {
  LocalWindow w;
  addFreeKeyframesAndLandmarks(map, keyframe, options, &w);
  addObservations(map, options, &w);
  // Nothing holds a window whose keyframes share no landmark with the rest of the map
  // (the first ones after the tracker re-anchored, tracker.h): its oldest keyframe does.
  auto& kfs = w.problem.keyframes;
  if (std::none_of(kfs.begin(), kfs.end(), [](const auto& k) { return k.fixed; }))
    kfs[std::min_element(w.kf_ids.begin(), w.kf_ids.end()) - w.kf_ids.begin()].fixed = true;
  return w;
}

/// The adjusted poses (of the free keyframes) and landmarks into the map; call with the map locked.
void writeBack(Map* map, const LocalWindow& w, const BundleResult& r) {
  for (size_t k = 0; k < w.kf_ids.size(); ++k)
    if (!w.problem.keyframes[k].fixed)
      if (KeyFrame* kf = map->keyframe(w.kf_ids[k])) kf->T_w_c = r.T_w_c[k];
  for (size_t i = 0; i < w.point_ids.size(); ++i)
    if (MapPoint* p = map->point(w.point_ids[i])) p->p_w = r.points[i];
  for (size_t i = 0; i < w.line_ids.size(); ++i)
    if (MapLine* l = map->line(w.line_ids[i])) {
      l->P_w = r.lines[i].first;
      l->Q_w = r.lines[i].second;
    }
}

/// Outlying observations are dropped (the landmark stays if others support it); call with the map locked.
void dropOutlierObservations(Map* map, const LocalWindow& w, const BundleResult& r) {
  for (size_t o = 0; o < w.problem.point_obs.size(); ++o) {
    if (!r.point_obs_outlier[o]) continue;
    const auto& obs = w.problem.point_obs[o];
    MapPoint* p = map->point(w.point_ids[obs.point]);
    KeyFrame* kf = map->keyframe(w.kf_ids[obs.keyframe]);
    if (!p || !kf) continue;
    auto it = p->observations.find(kf->id);
    if (it == p->observations.end()) continue;
    kf->point_ids[it->second] = kNoId;
    p->observations.erase(it);
    if (p->observations.empty()) map->erasePoint(p->id);
  }
  for (size_t o = 0; o < w.problem.line_obs.size(); ++o) {
    if (!r.line_obs_outlier[o]) continue;
    const auto& obs = w.problem.line_obs[o];
    MapLine* l = map->line(w.line_ids[obs.line]);
    KeyFrame* kf = map->keyframe(w.kf_ids[obs.keyframe]);
    if (!l || !kf) continue;
    auto it = l->observations.find(kf->id);
    if (it == l->observations.end()) continue;
    kf->line_ids[it->second] = kNoId;
    l->observations.erase(it);
    if (l->observations.empty()) map->eraseLine(l->id);
  }
}

// Validated before anything is built from them, so that errors name the `mapper.` key.
const LocalMapperOptions& validated(const LocalMapperOptions& o) {
  o.validate();
  return o;
}
}  // namespace

void LocalMapperOptions::validate() const {
  auto require = [](bool ok, const char* key, const std::string& range, double value) {
    requireOption(ok, "mapper", key, range, value);
  };
  require(ba_keyframes >= 1, "ba_keyframes", ">= 1", ba_keyframes);
  require(ba_fixed_keyframes >= 0, "ba_fixed_keyframes", ">= 0", ba_fixed_keyframes);
  require(min_covisible_points >= 1, "min_covisible_points", ">= 1", min_covisible_points);
  require(cull_found_ratio >= 0 && cull_found_ratio <= 1, "cull_found_ratio", "in [0, 1]", cull_found_ratio);
  require(cull_min_visible >= 1, "cull_min_visible", ">= 1", cull_min_visible);
  require(cull_single_after >= 1, "cull_single_after", ">= 1", cull_single_after);
  require(ba.max_iterations >= 1, "ba_iterations", ">= 1", ba.max_iterations);
  require(ba.refine_iterations >= 0, "ba_refine_iterations", ">= 0", ba.refine_iterations);
  require(ba.max_time_s >= 0, "ba_max_time_s", ">= 0 (0: no budget)", ba.max_time_s);
  require(ba.model.depth_sigma_coeff > 0, "depth_sigma_coeff", "> 0", ba.model.depth_sigma_coeff);
}

LocalMapper::LocalMapper(Map* map, PinholeCamera camera, LocalMapperOptions options)
    : map_(map), camera_(std::move(camera)), options_(validated(options)), adjuster_(options_.ba) {}

void LocalMapper::processKeyframe(Id keyframe, const cv::Mat& depth_m) {
  if (options_.use_lines) createLines(keyframe, depth_m);
  if (options_.local_ba) localBundleAdjustment(keyframe);
  cull(keyframe);
}

void LocalMapper::createLines(Id keyframe, const cv::Mat& depth_m) {
  std::vector<Segment2D> segments;
  std::vector<Id> line_ids;
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    const KeyFrame* kf = map_->keyframe(keyframe);
    if (!kf) return;
    segments = kf->features.lines;
    line_ids = kf->line_ids;
  }
  if (segments.empty() || depth_m.empty()) return;
  // Both methods are tried on every segment so that the two rates compare like with like;
  // only fitted segments not yet matched to a map line become new map lines.
  int built_fit = 0, built_end = 0;
  std::vector<std::pair<int, LineSegment3D>> fresh;
  for (size_t i = 0; i < segments.size(); ++i) {
    const auto fitted = fitLine3D(segments[i].p_raw, segments[i].q_raw, depth_m, camera_, options_.line_fit);
    built_fit += fitted.has_value();
    built_end += backprojectEndpoints(segments[i].p_raw, segments[i].q_raw, depth_m, camera_, options_.line_fit).has_value();
    if (fitted && line_ids[i] == kNoId) fresh.emplace_back(static_cast<int>(i), *fitted);
  }
  stats_.rate_fitting.add(built_fit, static_cast<int>(segments.size()));
  stats_.rate_endpoints.add(built_end, static_cast<int>(segments.size()));

  std::lock_guard<std::mutex> lock(map_->mutex());
  KeyFrame* kf = map_->keyframe(keyframe);
  if (!kf) return;
  for (const auto& [index, seg] : fresh) {
    MapLine l;
    l.P_w = kf->T_w_c * seg.P_c;  // the pose now: a loop correction may have moved it meanwhile
    l.Q_w = kf->T_w_c * seg.Q_c;
    l.descriptor = kf->features.line_descriptors.row(index).clone();
    l.first_keyframe = keyframe;
    const Id id = map_->addLine(std::move(l));
    map_->addLineObservation(keyframe, index, id);
    ++stats_.lines_created;
  }
}

void LocalMapper::localBundleAdjustment(Id keyframe) {
  LocalWindow window;
  uint64_t corrections = 0;
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    if (!map_->keyframe(keyframe)) return;
    corrections = map_->corrections();
    window = gatherLocalWindow(map_, keyframe, options_);
  }
  if (window.problem.point_obs.empty()) return;
  const BundleResult r = adjuster_.adjust(camera_, window.problem);
  ++stats_.ba_runs;
  stats_.ba_ms.push_back(r.time_ms);
  if (!r.ok()) {
    kLog.debug(str("local BA at keyframe ", keyframe, ": ", toString(r.status)));
    return;
  }
  std::lock_guard<std::mutex> lock(map_->mutex());
  // A loop correction landed while this BA ran (on the loop thread): its absolute result
  // would undo the correction; it is dropped, the next keyframe's BA works on the moved map.
  if (map_->corrections() == corrections)
    writeBack(map_, window, r);
  else
    ++stats_.ba_dropped;
  dropOutlierObservations(map_, window, r);
}

void LocalMapper::cull(Id keyframe) {
  std::lock_guard<std::mutex> lock(map_->mutex());
  std::vector<Id> bad_points, bad_lines;
  for (const auto& [id, p] : map_->points()) {
    const bool rarely_found = p.visible >= options_.cull_min_visible && p.found < options_.cull_found_ratio * p.visible;
    const bool lonely = p.observations.size() < 2 && keyframe - p.first_keyframe >= options_.cull_single_after;
    if (rarely_found || lonely) bad_points.push_back(id);
  }
  for (const auto& [id, l] : map_->lines()) {
    const bool rarely_found = l.visible >= options_.cull_min_visible && l.found < options_.cull_found_ratio * l.visible;
    const bool lonely = l.observations.size() < 2 && keyframe - l.first_keyframe >= options_.cull_single_after;
    if (rarely_found || lonely) bad_lines.push_back(id);
  }
  for (Id id : bad_points) map_->erasePoint(id);
  for (Id id : bad_lines) map_->eraseLine(id);
  stats_.points_culled += static_cast<int>(bad_points.size());
  stats_.lines_culled += static_cast<int>(bad_lines.size());
}

}  // namespace plslam
