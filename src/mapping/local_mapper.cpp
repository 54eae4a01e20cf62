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

/// What differs between the two kinds of landmark for the window's bookkeeping: how the map
/// finds and erases one, and which slots of a keyframe hold their ids.
struct PointKind {
  static MapPoint* get(Map* map, Id id) { return map->point(id); }
  static void erase(Map* map, Id id) { map->erasePoint(id); }
  static std::vector<Id>& slots(KeyFrame* kf) { return kf->point_ids; }
  static int landmark(const BundleProblem::PointObs& obs) { return obs.point; }
};
struct LineKind {
  static MapLine* get(Map* map, Id id) { return map->line(id); }
  static void erase(Map* map, Id id) { map->eraseLine(id); }
  static std::vector<Id>& slots(KeyFrame* kf) { return kf->line_ids; }
  static int landmark(const BundleProblem::LineObs& obs) { return obs.line; }
};

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

/// Every observation of the landmarks `ids` from keyframes in the window or joining it, made
/// into the problem's observation `make(keyframe index, landmark index, keyframe, feature index)`.
template <typename Kind, typename MakeObservation>
void addObservationsOf(Map* map, const std::vector<Id>& ids, const LocalMapperOptions& options, LocalWindow* w,
                       MakeObservation make) {
  for (size_t i = 0; i < ids.size(); ++i)
    for (const auto& [kf, idx] : Kind::get(map, ids[i])->observations) {
      const int k = windowKeyframeIndex(map, kf, options, w);
      if (k >= 0) make(k, static_cast<int>(i), *map->keyframe(kf), idx);
    }
}

void addObservations(Map* map, const LocalMapperOptions& options, LocalWindow* w) {
  BundleProblem& problem = w->problem;
  addObservationsOf<PointKind>(map, w->point_ids, options, w, [&](int k, int i, const KeyFrame& kf, int idx) {
    const Keypoint& kp = kf.features.points[idx];
    problem.point_obs.push_back({k, i, kp.uv, kp.octave, kp.depth_m});
  });
  addObservationsOf<LineKind>(map, w->line_ids, options, w, [&](int k, int i, const KeyFrame& kf, int idx) {
    const Segment2D& s = kf.features.lines[idx];
    problem.line_obs.push_back({k, i, s.p, s.q, s.octave});
  });
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

/// The outlying observations `obs` of the landmarks `ids` are dropped (a landmark stays while
/// others support it); call with the map locked.
template <typename Kind, typename Observation>
void dropOutliersOf(Map* map, const LocalWindow& w, const std::vector<Id>& ids, const std::vector<Observation>& obs,
                    const std::vector<bool>& outlier) {
  for (size_t o = 0; o < obs.size(); ++o) {
    if (!outlier[o]) continue;
    auto* landmark = Kind::get(map, ids[Kind::landmark(obs[o])]);
    KeyFrame* kf = map->keyframe(w.kf_ids[obs[o].keyframe]);
    if (!landmark || !kf) continue;
    auto it = landmark->observations.find(kf->id);
    if (it == landmark->observations.end()) continue;
    Kind::slots(kf)[it->second] = kNoId;
    landmark->observations.erase(it);
    if (landmark->observations.empty()) Kind::erase(map, landmark->id);
  }
}

void dropOutlierObservations(Map* map, const LocalWindow& w, const BundleResult& r) {
  dropOutliersOf<PointKind>(map, w, w.point_ids, w.problem.point_obs, r.point_obs_outlier);
  dropOutliersOf<LineKind>(map, w, w.line_ids, w.problem.line_obs, r.line_obs_outlier);
}

/// Landmarks rarely found where they were predicted, and those still seen by one keyframe
/// `cull_single_after` keyframes after their first.
template <typename Landmark>
std::vector<Id> landmarksToCull(const std::map<Id, Landmark>& landmarks, Id keyframe, const LocalMapperOptions& o) {
  std::vector<Id> bad;
  for (const auto& [id, l] : landmarks) {
    const bool rarely_found = l.visible >= o.cull_min_visible && l.found < o.cull_found_ratio * l.visible;
    const bool lonely = l.observations.size() < 2 && keyframe - l.first_keyframe >= o.cull_single_after;
    if (rarely_found || lonely) bad.push_back(id);
  }
  return bad;
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
  {
    std::lock_guard<std::mutex> stats_lock(stats_mutex_);
    stats_.rate_fitting.add(built_fit, static_cast<int>(segments.size()));
    stats_.rate_endpoints.add(built_end, static_cast<int>(segments.size()));
  }

  std::lock_guard<std::mutex> lock(map_->mutex());
  KeyFrame* kf = map_->keyframe(keyframe);
  if (!kf) return;
  int created = 0;
  for (const auto& [index, seg] : fresh) {
    MapLine l;
    l.P_w = kf->T_w_c * seg.P_c;  // the pose now: a loop correction may have moved it meanwhile
    l.Q_w = kf->T_w_c * seg.Q_c;
    l.descriptor = kf->features.line_descriptors.row(index).clone();
    l.first_keyframe = keyframe;
    const Id id = map_->addLine(std::move(l));
    map_->addLineObservation(keyframe, index, id);
    ++created;
  }
  std::lock_guard<std::mutex> stats_lock(stats_mutex_);
  stats_.lines_created += created;
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
  {
    std::lock_guard<std::mutex> stats_lock(stats_mutex_);
    ++stats_.ba_runs;
    stats_.ba_ms.push_back(r.time_ms);
  }
  if (!r.ok()) {
    kLog.debug(str("local BA at keyframe ", keyframe, ": ", toString(r.status)));
    return;
  }
  std::lock_guard<std::mutex> lock(map_->mutex());
  // A loop correction landed while this BA ran (on the loop thread): its absolute result
  // would undo the correction; it is dropped, the next keyframe's BA works on the moved map.
  if (map_->corrections() == corrections) {
    writeBack(map_, window, r);
  } else {
    std::lock_guard<std::mutex> stats_lock(stats_mutex_);
    ++stats_.ba_dropped;
  }
  dropOutlierObservations(map_, window, r);
}

void LocalMapper::cull(Id keyframe) {
  std::lock_guard<std::mutex> lock(map_->mutex());
  const std::vector<Id> bad_points = landmarksToCull(map_->points(), keyframe, options_);
  const std::vector<Id> bad_lines = landmarksToCull(map_->lines(), keyframe, options_);
  for (Id id : bad_points) map_->erasePoint(id);
  for (Id id : bad_lines) map_->eraseLine(id);
  std::lock_guard<std::mutex> stats_lock(stats_mutex_);
  stats_.points_culled += static_cast<int>(bad_points.size());
  stats_.lines_culled += static_cast<int>(bad_lines.size());
}

}  // namespace plslam
