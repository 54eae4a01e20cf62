#include "frontend/tracker.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <set>

#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"
#include "features/matching.h"
#include "frontend/frame_refinement.h"

namespace plslam {

namespace {
const Logger kLog("frontend");

/// Entries of a per-feature match list that hold a landmark.
int matchedCount(const std::vector<Id>& ids) {
  return static_cast<int>(ids.size() - std::count(ids.begin(), ids.end(), kNoId));
}
}

const char* toString(TrackingStatus s) {
  switch (s) {
    case TrackingStatus::kInitialized: return "initialized";
    case TrackingStatus::kOk: return "ok";
    case TrackingStatus::kRelocalized: return "relocalized";
    case TrackingStatus::kReanchored: return "reanchored";
    case TrackingStatus::kNotInitialized: return "not_initialized";
    case TrackingStatus::kFewMatches: return "few_matches";
    case TrackingStatus::kNoFeatures: return "no_features";
  }
  return "unknown";
}

const char* toString(TrackingMethod m) {
  switch (m) {
    case TrackingMethod::kNone: return "none";
    case TrackingMethod::kInitialisation: return "initialisation";
    case TrackingMethod::kMotionModel: return "motion_model";
    case TrackingMethod::kReferenceKeyframe: return "reference_keyframe";
    case TrackingMethod::kWideWindow: return "wide_window";
    case TrackingMethod::kRelocalisation: return "relocalisation";
    case TrackingMethod::kReanchor: return "reanchor";
  }
  return "unknown";
}

void TrackerOptions::validate() const {
  auto require = [](bool ok, const char* key, const std::string& range, double value) {
    requireOption(ok, "tracker", key, range, value);
  };
  require(min_inliers >= 1, "min_inliers", ">= 1", min_inliers);
  require(wide_radius_px > 0 && narrow_radius_px > 0, "wide_radius_px and narrow_radius_px", "> 0",
          std::min(wide_radius_px, narrow_radius_px));
  require(wide_fallback_factor >= 0, "wide_fallback_factor", ">= 0 (<= 1 turns it off)", wide_fallback_factor);
  require(min_pnp_points >= 4, "min_pnp_points", ">= 4 (PnP needs four points)", min_pnp_points);
  require(pnp_iterations >= 1, "pnp_iterations", ">= 1", pnp_iterations);
  require(pnp_error_px > 0, "pnp_error_px", "> 0", pnp_error_px);
  require(relocalisation.max_candidates >= 1, "relocalisation_candidates", ">= 1", relocalisation.max_candidates);
  require(relocalisation.min_relative_score >= 0 && relocalisation.min_relative_score <= 1,
          "relocalisation_min_relative_score", "in [0, 1]", relocalisation.min_relative_score);
  require(relocalisation_recent_keyframes >= 1, "relocalisation_recent_keyframes", ">= 1", relocalisation_recent_keyframes);
  require(near_plane_m > 0, "near_plane_m", "> 0", near_plane_m);
  require(max_speed_m_s > 0, "max_speed_m_s", "> 0", max_speed_m_s);
  require(reanchor_after_s >= 0, "reanchor_after_s", ">= 0 (0 turns it off)", reanchor_after_s);
}

Tracker::Tracker(Map* map, PinholeCamera camera, TrackerOptions options, std::shared_ptr<const VocabularySet> vocabulary)
    : map_(map),
      camera_(std::move(camera)),
      options_(options),
      optimizer_(options.optimizer),
      places_(std::move(vocabulary)) {
  options_.validate();
  std::lock_guard<std::mutex> lock(map_->mutex());
  if (!map_->keyframes().empty()) {
    // A loaded map: start lost, so the first frame is placed by relocalisation in it.
    have_last_ = lost_ = search_all_keyframes_ = true;
    reference_kf_ = map_->keyframes().begin()->first;
    for (const auto& [id, kf] : map_->keyframes()) places_.add(id, kf.features);
  }
}

TrackingResult Tracker::track(TimeNs t_ns, const FrameFeatures& f) {
  if (!have_last_ && options_.localization_only) {
    TrackingResult r;
    r.reason = "localisation only, and the map is empty";
    return r;
  }
  have_frame_words_ = false;  // a new frame: its words are described on first use
  if (!have_last_) return initialise(t_ns, f);
  times_ = StageTimes();
  TrackingResult r = trackInitialised(t_ns, f);
  r.times = times_;
  return r;
}

TrackingResult Tracker::trackInitialised(TimeNs t_ns, const FrameFeatures& f) {
  TrackingResult r;
  if (static_cast<int>(f.points.size()) + static_cast<int>(f.lines.size()) < options_.min_inliers) {
    r.status = TrackingStatus::kNoFeatures;
    r.reason = str(f.points.size(), " points and ", f.lines.size(), " lines in the image");
  }
  Matches m;
  Attempt a;
  if (r.reason.empty()) {
    if (!lost_) {
      a = trackFromLastPose(nsToSeconds(t_ns - t_last_ns_), f, &m, &r);
    } else {
      a = relocalize(f, &m);
      if (a.ok) r.method = TrackingMethod::kRelocalisation;
      else if (shouldReanchor(t_ns, f)) return reanchor(t_ns, f);
    }
    if (!a.ok) r.reason = a.reason;
    r.status = a.ok ? (lost_ ? TrackingStatus::kRelocalized : TrackingStatus::kOk) : TrackingStatus::kFewMatches;
  }
  const bool ok = a.ok;
  const SE3 T_w_c = a.T_w_c;
  if (!ok) {
    r.method = TrackingMethod::kNone;
    if (!lost_) {
      ++lost_events_;
      kLog.warn(str("lost at t=", formatSecondsStamp(t_ns), ": ", r.reason));
    }
    lost_ = true;
    have_velocity_ = false;
    return r;
  }
  const bool relocalised = lost_ || r.method == TrackingMethod::kRelocalisation;
  if (lost_) {
    ++relocalisations_;
    kLog.info(str("relocalised at t=", formatSecondsStamp(t_ns)));
  }
  lost_ = false;
  search_all_keyframes_ = false;
  if (!options_.localization_only) {
    countVisibleAndFound(m, &r);
  } else {
    r.matched_points = matchedCount(m.point_ids);
    r.matched_lines = matchedCount(m.line_ids);
    reference_kf_ = keyframeSharingMost(m, reference_kf_);
  }
  r.inliers = r.matched_points + r.matched_lines;
  r.T_w_c = T_w_c;
  r.point_matches = m.point_ids;
  r.line_matches = m.line_ids;
  if (kLog.enabled(LogLevel::kDebug))
    kLog.debug(str("t=", formatSecondsStamp(t_ns), " points ", f.points.size(), " matched ", r.matched_points, " lines ",
                   f.lines.size(), " matched ", r.matched_lines, " moved ", (T_w_last_.inverse() * T_w_c).translation().norm()));
  T_prev_last_ = T_w_last_.inverse() * T_w_c;
  have_velocity_ = !relocalised;  // the last pose before the loss says nothing of the motion now
  T_w_last_ = T_w_c;
  t_last_ns_ = t_ns;
  ++frames_since_kf_;
  const StageTimer keyframe_timer(&times_, Stage::kKeyframe);
  if (!options_.localization_only) place_kf_ = keyframeSharingMost(m, reference_kf_);
  if (!options_.localization_only && needKeyframe(T_w_c, r.inliers)) {
    r.keyframe_id = makeKeyframe(t_ns, T_w_c, f, m);
    r.new_keyframe = true;
  }
  r.reference_keyframe = reference_kf_;
  return r;
}

Tracker::Attempt Tracker::trackFromLastPose(double dt_s, const FrameFeatures& f, Matches* m, TrackingResult* r) {
  const SE3 predicted = have_velocity_ ? T_w_last_ * T_prev_last_ : T_w_last_;
  const LocalMap local = takeLocalMap();
  r->local_points = static_cast<int>(local.point_ids.size());
  r->local_lines = static_cast<int>(local.line_ids.size());
  // Each way in turn; a pose that would need an impossible speed is a wrong one (a few
  // matches on a blurred frame can agree on it) and counts as a failure.
  auto plausible = [&](Attempt a) {
    const double jump_m = (T_w_last_.inverse() * a.T_w_c).translation().norm();
    if (a.ok && dt_s > 0 && jump_m > options_.max_speed_m_s * dt_s)
      a = {false, a.T_w_c, a.inliers, str("a jump of ", jump_m, " m in ", dt_s, " s")};
    return a;
  };
  Attempt a = plausible(trackWithPrediction(local, predicted, options_.wide_radius_px, f, m));
  r->inliers = a.inliers;
  if (a.ok) {
    r->method = TrackingMethod::kMotionModel;
    return a;
  }
  const std::string motion_failure = a.reason;
  std::string why = "motion model: " + motion_failure;
  if (options_.reference_fallback) {
    a = plausible(trackReferenceKeyframe(local, predicted, f, m));
    if (a.ok) r->method = TrackingMethod::kReferenceKeyframe;
    else why += "; reference keyframe: " + a.reason;
  }
  if (!a.ok && options_.wide_fallback_factor > 1) {
    a = plausible(trackWithPrediction(local, predicted, options_.wide_radius_px * options_.wide_fallback_factor, f, m));
    if (a.ok) r->method = TrackingMethod::kWideWindow;
    else why += "; wide window: " + a.reason;
  }
  // The last pose itself may be wrong (a walker dragged it), and then every attempt above is
  // searched around it or refused by the speed limit: place recognition does not need it.
  if (!a.ok && options_.relocalisation_fallback) {
    a = relocalize(f, m);
    if (a.ok) r->method = TrackingMethod::kRelocalisation;
    else why += "; " + a.reason;
  }
  if (a.ok) {
    r->inliers = a.inliers;
    if (kLog.enabled(LogLevel::kDebug)) kLog.debug(str("motion model failed (", motion_failure, "), ", toString(r->method), " tracked"));
  } else {
    a.reason = "tracking: " + why;
  }
  return a;
}

Tracker::Attempt Tracker::trackWithPrediction(const LocalMap& local, const SE3& T_w_c, double radius,
                                              const FrameFeatures& f, Matches* m) {
  *m = Matches();
  searchLocalMap(local, T_w_c, f, radius, m, false);
  return refineWithLocalMap(local, T_w_c, f, m, options_.min_inliers);
}

Tracker::Attempt Tracker::refineWithLocalMap(const LocalMap& local, const SE3& T_w_c, const FrameFeatures& f, Matches* m,
                                             int min_inliers) {
  Attempt a;
  PoseOnlyResult pr = optimizePose(T_w_c, f, m);
  if (pr.converged) {
    searchLocalMap(local, pr.T_w_c, f, options_.narrow_radius_px, m, true);
    pr = optimizePose(pr.T_w_c, f, m);
    a.ok = pr.converged && pr.inliers >= min_inliers;
  }
  a.T_w_c = pr.T_w_c;
  a.inliers = pr.inliers;
  if (!a.ok) a.reason = str(pr.inliers, " pose inliers (", toString(pr.status), ")");
  return a;
}

Tracker::Attempt Tracker::trackReferenceKeyframe(const LocalMap& local, const SE3& predicted, const FrameFeatures& f,
                                                 Matches* m) {
  Attempt a;
  {
    const StageTimer timer(&times_, Stage::kSearch);
    std::lock_guard<std::mutex> lock(map_->mutex());
    *m = matchKeyframe(reference_kf_, f);
  }
  const int n = matchedCount(m->point_ids) + matchedCount(m->line_ids);
  if (n < options_.min_vocabulary_matches) {
    a.reason = str(n, " vocabulary matches");
    return a;
  }
  // PnP does not need the prediction, so it survives any rotation; lines alone start from it.
  SE3 start = predicted;
  if (matchedCount(m->point_ids) >= options_.min_pnp_points) poseByPnP(f, m, &start);
  return refineWithLocalMap(local, start, f, m, options_.min_inliers);
}

Tracker::Matches Tracker::matchKeyframe(Id kf_id, const FrameFeatures& f) {
  Matches m;
  m.point_ids.assign(f.points.size(), kNoId);
  m.line_ids.assign(f.lines.size(), kNoId);
  const KeyFrame* kf = map_->keyframe(kf_id);
  if (!kf) return m;
  BruteForceOptions points{options_.max_descriptor_distance, options_.ratio, true};
  BruteForceOptions lines{options_.max_line_descriptor_distance, options_.ratio, true};
  std::vector<DescriptorMatch> pm, lm;
  if (const FrameWords* kw = keyframeWords(kf_id)) {
    // Only the keyframe's features that observe a landmark take part.
    std::vector<int> kp_nodes = kw->point_nodes, kl_nodes = kw->line_nodes;
    for (size_t i = 0; i < kp_nodes.size(); ++i)
      if (kf->point_ids[i] == kNoId || !map_->point(kf->point_ids[i])) kp_nodes[i] = -1;
    for (size_t i = 0; i < kl_nodes.size(); ++i)
      if (kf->line_ids[i] == kNoId || !map_->line(kf->line_ids[i])) kl_nodes[i] = -1;
    const FrameWords& fw = frameWords(f);
    pm = matchByVocabulary(kf->features.point_descriptors, kp_nodes, f.point_descriptors, fw.point_nodes, points);
    if (options_.use_lines)
      lm = matchByVocabulary(kf->features.line_descriptors, kl_nodes, f.line_descriptors, fw.line_nodes, lines);
  } else {
    pm = matchBruteForce(kf->features.point_descriptors, f.point_descriptors, points);
    if (options_.use_lines) lm = matchBruteForce(kf->features.line_descriptors, f.line_descriptors, lines);
  }
  for (const DescriptorMatch& d : pm)
    if (kf->point_ids[d.query] != kNoId && map_->point(kf->point_ids[d.query])) m.point_ids[d.train] = kf->point_ids[d.query];
  for (const DescriptorMatch& d : lm)
    if (kf->line_ids[d.query] != kNoId && map_->line(kf->line_ids[d.query])) m.line_ids[d.train] = kf->line_ids[d.query];
  return m;
}

bool Tracker::poseByPnP(const FrameFeatures& f, Matches* m, SE3* T_w_c) {
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  std::vector<int> keypoint;
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    for (size_t k = 0; k < m->point_ids.size(); ++k) {
      const MapPoint* p = m->point_ids[k] == kNoId ? nullptr : map_->point(m->point_ids[k]);
      if (!p) continue;
      object.emplace_back(p->p_w.x(), p->p_w.y(), p->p_w.z());
      image.emplace_back(f.points[k].uv.x(), f.points[k].uv.y());
      keypoint.push_back(static_cast<int>(k));
    }
  }
  if (static_cast<int>(object.size()) < options_.min_pnp_points) return false;
  const StageTimer timer(&times_, Stage::kPoseOptimisation);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  // K may hold a negative fx or fy (camera/pinhole_camera.h): OpenCV's EPnP, RANSAC
  // reprojection test and refinement keep the sign (tests/system/test_mirrored_camera.cpp
  // relocalises with fy < 0).
  if (!cv::solvePnPRansac(object, image, cv::Mat(camera_.K()), cv::noArray(), rvec, tvec, false, options_.pnp_iterations,
                          static_cast<float>(options_.pnp_error_px), 0.99, inliers, cv::SOLVEPNP_EPNP) ||
      static_cast<int>(inliers.size()) < options_.min_pnp_points)
    return false;
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Re(r, c) = R.at<double>(r, c);
  *T_w_c = SE3(Re, Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2))).inverse();
  std::vector<Id> kept(m->point_ids.size(), kNoId);
  for (int i : inliers) kept[keypoint[i]] = m->point_ids[keypoint[i]];
  m->point_ids = std::move(kept);
  return true;
}

const FrameWords* Tracker::keyframeWords(Id kf) {
  if (!places_.enabled()) return nullptr;
  if (const FrameWords* w = places_.words(kf)) return w;
  const KeyFrame* k = map_->keyframe(kf);
  if (!k) return nullptr;
  places_.add(kf, k->features);  // a loaded map's keyframe, or one made before the index
  return places_.words(kf);
}

const FrameWords& Tracker::frameWords(const FrameFeatures& f) {
  if (!have_frame_words_) {
    frame_words_ = places_.describe(f);
    have_frame_words_ = true;
  }
  return frame_words_;
}

int Tracker::pointsWithDepth(const FrameFeatures& f) const {
  int n = 0;
  for (const Keypoint& k : f.points) n += std::isfinite(k.depth_m) && k.depth_m > 0 && k.depth_m < options_.max_depth_m;
  return n;
}

TrackingResult Tracker::initialise(TimeNs t_ns, const FrameFeatures& f) {
  const int with_depth = pointsWithDepth(f);
  if (with_depth < options_.min_init_points) {
    TrackingResult r;
    r.status = TrackingStatus::kNotInitialized;
    r.reason = str(with_depth, " keypoints with depth, ", options_.min_init_points, " needed to initialise");
    return r;
  }
  have_last_ = true;
  kLog.info(str("initialised at t=", formatSecondsStamp(t_ns), " with ", with_depth, " points"));
  return startFromDepth(t_ns, f, SE3());  // the first keyframe defines the world frame
}

bool Tracker::shouldReanchor(TimeNs t_ns, const FrameFeatures& f) const {
  // A loaded map not yet found, or a map that must not change, has no "last pose" to go on from.
  if (options_.reanchor_after_s <= 0 || options_.localization_only || search_all_keyframes_) return false;
  return nsToSeconds(t_ns - t_last_ns_) >= options_.reanchor_after_s && pointsWithDepth(f) >= options_.min_init_points;
}

TrackingResult Tracker::reanchor(TimeNs t_ns, const FrameFeatures& f) {
  ++reanchors_;
  kLog.warn(str("re-anchored at t=", formatSecondsStamp(t_ns), ": lost for ", nsToSeconds(t_ns - t_last_ns_),
                " s and not relocalised; tracking goes on from a new keyframe at the last tracked pose"));
  lost_ = false;
  have_velocity_ = false;
  TrackingResult r = startFromDepth(t_ns, f, T_w_last_);
  r.status = TrackingStatus::kReanchored;
  r.method = TrackingMethod::kReanchor;
  r.times = times_;
  return r;
}

TrackingResult Tracker::startFromDepth(TimeNs t_ns, const FrameFeatures& f, const SE3& T_w_c) {
  TrackingResult r;
  Matches none;
  none.point_ids.assign(f.points.size(), kNoId);
  none.line_ids.assign(f.lines.size(), kNoId);
  r.keyframe_id = makeKeyframe(t_ns, T_w_c, f, none);
  r.new_keyframe = true;
  r.reference_keyframe = reference_kf_;
  r.status = TrackingStatus::kInitialized;
  r.method = TrackingMethod::kInitialisation;
  r.T_w_c = T_w_c;
  r.inliers = pointsWithDepth(f);
  T_w_last_ = T_w_c;
  t_last_ns_ = t_ns;
  return r;
}

const std::vector<std::pair<Id, int>>& Tracker::referenceCovisible() {
  if (covisible_of_ != reference_kf_) {
    covisible_ = map_->covisible(reference_kf_, options_.covisible_min_shared);
    covisible_of_ = reference_kf_;
  }
  return covisible_;
}

std::vector<Id> Tracker::localKeyframes() {
  // The reference keyframe, its best covisible keyframes and the most recent ones.
  std::vector<Id> out;
  std::set<Id> seen;
  auto add = [&](Id id) {
    if (static_cast<int>(out.size()) < options_.local_keyframes * 2 && seen.insert(id).second) out.push_back(id);
  };
  add(reference_kf_);
  const auto& cov = referenceCovisible();
  for (size_t i = 0; i < cov.size() && static_cast<int>(i) < options_.local_keyframes; ++i) add(cov[i].first);
  const auto& kfs = map_->keyframes();
  if (options_.localization_only) {
    // No new keyframes: the reference's neighbours in time stand in for the recent ones.
    auto after = kfs.upper_bound(reference_kf_);
    auto before = kfs.lower_bound(reference_kf_);
    for (int n = 0; n < options_.local_keyframes / 2;) {
      const bool more_after = after != kfs.end(), more_before = before != kfs.begin();
      if (!more_after && !more_before) break;
      if (more_after) add((after++)->first), ++n;
      if (more_before) add((--before)->first), ++n;
    }
    return out;
  }
  int recent = 0;
  for (auto it = kfs.rbegin(); it != kfs.rend() && recent < options_.local_keyframes / 2; ++it, ++recent) add(it->first);
  return out;
}

Id Tracker::keyframeSharingMost(const Matches& m, Id fallback) const {
  // Every matched point votes. Letting only 100 of them vote (997ee04) cut this stage from
  // 0.44-0.47 to 0.13-0.14 ms a frame at the end of an 11-lap run, but the run made 11-13 %
  // more keyframes, took more memory, and its tracking time grew along the run instead of
  // staying flat (docs/RESULTS.md, "Long run after the place-keyframe vote").
  std::lock_guard<std::mutex> lock(map_->mutex());
  if (map_->keyframes().empty()) return fallback;
  // Counted by keyframe id (keyframes are never erased, so the ids are dense): one array a
  // frame rather than a hash node per keyframe.
  std::vector<int> shared(static_cast<size_t>(map_->keyframes().rbegin()->first) + 1, 0);
  for (Id id : m.point_ids)
    if (const MapPoint* p = id == kNoId ? nullptr : map_->point(id))
      for (const auto& [kf, idx] : p->observations)
        if (kf < static_cast<Id>(shared.size())) ++shared[static_cast<size_t>(kf)];
  // Ties go to the newer keyframe: while the camera explores, that is the one it made last.
  Id best_kf = fallback;
  int best = 0;
  for (Id kf = 0; kf < static_cast<Id>(shared.size()); ++kf) {
    const int n = shared[static_cast<size_t>(kf)];
    if (n > 0 && (n > best || (n == best && kf > best_kf))) best = n, best_kf = kf;
  }
  return best_kf;
}

Tracker::LocalMap Tracker::collectLocalMap() {
  LocalMap local;
  scratch_points_.clear(last_local_points_);
  scratch_lines_.clear(last_local_lines_);
  for (Id kf : localKeyframes()) {
    const KeyFrame* k = map_->keyframe(kf);
    if (!k) continue;
    for (Id p : k->point_ids)
      if (scratch_points_.insert(p)) local.point_ids.push_back(p);
    for (Id l : k->line_ids)
      if (scratch_lines_.insert(l)) local.line_ids.push_back(l);
  }
  last_local_points_ = local.point_ids.size();
  last_local_lines_ = local.line_ids.size();
  return local;
}

Tracker::LocalMap Tracker::takeLocalMap() {
  const StageTimer timer(&times_, Stage::kSearch);
  std::lock_guard<std::mutex> lock(map_->mutex());
  return collectLocalMap();
}

namespace {

/// Local-map points projected into the frame: those in view (optionally recorded in
/// `visible`) and not matched yet, with their predicted pixels and descriptors.
struct PointPredictions {
  std::vector<Id> ids;
  std::vector<PointPrediction> predictions;
  cv::Mat desc;
};

PointPredictions predictPoints(Map* map, const std::vector<Id>& point_ids, const SE3& T_c_w,
                               const PinholeCamera& camera, double near_plane_m, const IdSet& matched,
                               std::vector<Id>* visible) {
  PointPredictions out;
  out.desc.reserve(point_ids.size());
  for (Id id : point_ids) {
    MapPoint* p = map->point(id);
    if (!p) continue;  // culled by the mapper since the local map was taken
    const Eigen::Vector3d p_c = T_c_w * p->p_w;
    if (p_c.z() < near_plane_m) continue;
    const Eigen::Vector2d uv = camera.projectIdeal(p_c);
    if (!camera.inImage(uv)) continue;
    if (visible) visible->push_back(id);
    if (matched.contains(id)) continue;
    out.ids.push_back(id);
    out.predictions.push_back({uv, -1});
    out.desc.push_back(p->descriptor);
  }
  return out;
}

/// The same for lines: each clipped to the near plane, in view when an endpoint or the
/// midpoint projects into the image.
struct LinePredictions {
  std::vector<Id> ids;
  std::vector<LineSegment2D> segments;
  cv::Mat desc;
};

LinePredictions predictLines(Map* map, const std::vector<Id>& line_ids, const SE3& T_c_w, const PinholeCamera& camera,
                             double near, const IdSet& matched, std::vector<Id>* visible) {
  LinePredictions out;
  out.desc.reserve(line_ids.size());
  for (Id id : line_ids) {
    MapLine* l = map->line(id);
    if (!l) continue;
    Eigen::Vector3d P = T_c_w * l->P_w, Q = T_c_w * l->Q_w;
    if (P.z() < near && Q.z() < near) continue;
    // Clip the part behind the camera so the projection stays meaningful.
    if (P.z() < near) P = Q + (P - Q) * ((Q.z() - near) / (Q.z() - P.z()));
    if (Q.z() < near) Q = P + (Q - P) * ((P.z() - near) / (P.z() - Q.z()));
    const Eigen::Vector2d p = camera.projectIdeal(P), q = camera.projectIdeal(Q);
    if (!camera.inImage(p) && !camera.inImage(q) && !camera.inImage(0.5 * (p + q))) continue;
    if (visible) visible->push_back(id);
    if (matched.contains(id)) continue;
    out.ids.push_back(id);
    out.segments.push_back(LineSegment2D::fromEndpoints(p, q));
    out.desc.push_back(l->descriptor);
  }
  return out;
}

}  // namespace

void Tracker::searchLocalMap(const LocalMap& local, const SE3& T_w_c, const FrameFeatures& f, double radius, Matches* m,
                             bool record_visible) {
  const StageTimer timer(&times_, Stage::kSearch);
  std::lock_guard<std::mutex> lock(map_->mutex());
  if (m->point_ids.size() != f.points.size()) m->point_ids.assign(f.points.size(), kNoId);
  if (m->line_ids.size() != f.lines.size()) m->line_ids.assign(f.lines.size(), kNoId);
  if (record_visible) m->visible_points.clear(), m->visible_lines.clear();
  const SE3 T_c_w = T_w_c.inverse();
  // Landmarks matched in an earlier pass keep their keypoint; the rest are searched among
  // the keypoints still free.
  IdSet& matched_points = scratch_points_;
  matched_points.clear(m->point_ids.size());
  for (Id id : m->point_ids) matched_points.insert(id);
  std::vector<char> kp_taken(f.points.size());
  for (size_t k = 0; k < f.points.size(); ++k) kp_taken[k] = m->point_ids[k] != kNoId;
  const PointPredictions pts = predictPoints(map_, local.point_ids, T_c_w, camera_, options_.near_plane_m,
                                             matched_points, record_visible ? &m->visible_points : nullptr);
  std::vector<Eigen::Vector2d> kp_uv;
  std::vector<int> kp_octave;
  for (const Keypoint& k : f.points) {
    kp_uv.push_back(k.uv);
    kp_octave.push_back(k.octave);
  }
  PointProjectionOptions po;
  po.radius_px = radius;
  po.max_distance = options_.max_descriptor_distance;
  po.ratio = options_.ratio;
  po.octave_window = -1;
  if (record_visible && kLog.enabled(LogLevel::kDebug))
    kLog.debug(str("search: local map ", local.point_ids.size(), " points ", local.line_ids.size(), " lines, ",
                   m->visible_points.size(), " points in view, ", pts.predictions.size(), " searched"));
  const PointGrid grid(kp_uv, camera_.width, camera_.height);
  for (const DescriptorMatch& dm :
       matchPointsByProjection(pts.predictions, pts.desc, grid, kp_octave, f.point_descriptors, po, kp_taken))
    m->point_ids[dm.train] = pts.ids[dm.query];

  if (!options_.use_lines || f.lines.empty()) return;
  IdSet& matched_lines = scratch_lines_;
  matched_lines.clear(m->line_ids.size());
  for (Id id : m->line_ids) matched_lines.insert(id);
  std::vector<char> line_taken(f.lines.size());
  std::vector<LineSegment2D> segments;
  for (size_t k = 0; k < f.lines.size(); ++k) {
    line_taken[k] = m->line_ids[k] != kNoId;
    segments.push_back(LineSegment2D::fromEndpoints(f.lines[k].p, f.lines[k].q));
  }
  const LinePredictions lns = predictLines(map_, local.line_ids, T_c_w, camera_, options_.near_plane_m, matched_lines,
                                           record_visible ? &m->visible_lines : nullptr);
  LineProjectionOptions lo;
  lo.angle_deg = options_.line_angle_deg;
  // The wide first pass allows for the motion model's error.
  lo.distance_px = options_.line_distance_px * std::max(1.0, radius / options_.narrow_radius_px) * 0.5 +
                   options_.line_distance_px * 0.5;
  lo.max_distance = options_.max_line_descriptor_distance;
  for (const DescriptorMatch& dm :
       matchLinesByProjection(lns.segments, lns.desc, segments, f.line_descriptors, lo, line_taken))
    m->line_ids[dm.train] = lns.ids[dm.query];
}

void Tracker::countVisibleAndFound(const Matches& m, TrackingResult* r) {
  std::lock_guard<std::mutex> lock(map_->mutex());
  for (Id id : m.visible_points)
    if (MapPoint* p = map_->point(id)) ++p->visible;
  for (Id id : m.visible_lines)
    if (MapLine* l = map_->line(id)) ++l->visible;
  for (Id id : m.point_ids)
    if (MapPoint* p = id == kNoId ? nullptr : map_->point(id)) ++p->found, ++r->matched_points;
  for (Id id : m.line_ids)
    if (MapLine* l = id == kNoId ? nullptr : map_->line(id)) ++l->found, ++r->matched_lines;
}

PoseOnlyResult Tracker::optimizePose(const SE3& T_w_c, const FrameFeatures& f, Matches* m) {
  const StageTimer timer(&times_, Stage::kPoseOptimisation);
  FrameObservations obs = matchedObservations(f, m->point_ids, m->line_ids);
  PoseOnlyProblem problem;
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    problem = poseProblem(*map_, &obs, T_w_c);  // landmarks culled by the mapper meanwhile drop out
  }
  const PoseOnlyResult r = optimizer_.optimize(camera_, problem);
  // What stays matched: the inliers (every landmark still there when it did not converge).
  m->point_ids.assign(f.points.size(), kNoId);
  m->line_ids.assign(f.lines.size(), kNoId);
  for (size_t k = 0; k < obs.point_ids.size(); ++k)
    if (!r.converged || r.point_inlier[k]) m->point_ids[obs.point_index[k]] = obs.point_ids[k];
  for (size_t k = 0; k < obs.line_ids.size(); ++k)
    if (!r.converged || r.line_inlier[k]) m->line_ids[obs.line_index[k]] = obs.line_ids[k];
  return r;
}

Tracker::Attempt Tracker::relocalize(const FrameFeatures& f, Matches* m) {
  Attempt a;
  a.reason = "relocalisation failed: no keyframe matched";
  for (Id kf : relocalisationCandidates(f)) {
    {
      const StageTimer timer(&times_, Stage::kSearch);
      std::lock_guard<std::mutex> lock(map_->mutex());
      *m = matchKeyframe(kf, f);
    }
    SE3 start;
    if (!poseByPnP(f, m, &start)) continue;
    // The local map around the candidate, not around a reference from before the loss.
    const Id before = reference_kf_;
    reference_kf_ = kf;
    const Attempt refined = refineWithLocalMap(takeLocalMap(), start, f, m, options_.relocalisation_min_inliers);
    if (refined.ok) return refined;
    reference_kf_ = before;
    a.reason = str("relocalisation failed: best candidate ", refined.reason);
  }
  return a;
}

std::vector<Id> Tracker::relocalisationCandidates(const FrameFeatures& f) {
  std::vector<Id> out;
  if (f.points.size() < static_cast<size_t>(options_.min_pnp_points)) return out;
  if (places_.enabled()) {
    const FrameWords& words = frameWords(f);
    std::lock_guard<std::mutex> lock(map_->mutex());
    for (const PlaceScore& s : places_.query(words, options_.relocalisation))
      if (map_->keyframe(s.keyframe)) out.push_back(s.keyframe);
    return out;
  }
  // No vocabulary: the most recent keyframes (every one of a loaded map, not tracked yet).
  const bool all = search_all_keyframes_ || options_.localization_only;
  std::lock_guard<std::mutex> lock(map_->mutex());
  const auto& kfs = map_->keyframes();
  for (auto it = kfs.rbegin(); it != kfs.rend() && (all || static_cast<int>(out.size()) < options_.relocalisation_recent_keyframes); ++it)
    out.push_back(it->first);
  return out;
}

bool Tracker::needKeyframe(const SE3& T_w_c, int inliers) const {
  if (frames_since_kf_ < options_.keyframe_min_frames) return false;
  // A weakly supported pose (a blurred frame held by a few matches) would seed the map with
  // landmarks placed by that pose: wait for a frame that is tracked firmly.
  if (inliers < options_.keyframe_min_support) return false;
  std::lock_guard<std::mutex> lock(map_->mutex());
  // A frame sharing the most landmarks with a keyframe older than the recent ones sees a
  // place mapped before (a revisit): it needs a keyframe only when it tracks weakly or has
  // moved away from that keyframe, not by time, else every lap of a room adds keyframes.
  const bool revisit = place_kf_ != kNoId && map_->keyframe(place_kf_) && !isRecentKeyframe(place_kf_);
  if (!revisit && frames_since_kf_ >= options_.keyframe_max_frames) return true;
  if (inliers < options_.keyframe_min_inliers) return true;
  if (inliers < options_.keyframe_inlier_ratio * (revisit ? landmarksOf(place_kf_) : reference_kf_landmarks_))
    return true;
  const KeyFrame* ref = map_->keyframe(revisit ? place_kf_ : reference_kf_);
  if (!ref) return true;
  const SE3 T_ref_c = ref->T_w_c.inverse() * T_w_c;
  return T_ref_c.translation().norm() > options_.keyframe_max_translation_m ||
         T_ref_c.angle() * 180.0 / M_PI > options_.keyframe_max_rotation_deg;
}

bool Tracker::isRecentKeyframe(Id kf) const {
  const auto& kfs = map_->keyframes();
  int n = 0;
  for (auto it = kfs.rbegin(); it != kfs.rend() && n < options_.local_keyframes; ++it, ++n)
    if (it->first == kf) return true;
  return false;
}

int Tracker::landmarksOf(Id kf) const {
  const auto it = keyframe_landmarks_.find(kf);
  if (it != keyframe_landmarks_.end()) return it->second;
  const KeyFrame* k = map_->keyframe(kf);  // a keyframe of a loaded map: the points it observes
  return k ? static_cast<int>(std::count_if(k->point_ids.begin(), k->point_ids.end(), [](Id id) { return id != kNoId; }))
           : 0;
}

Id Tracker::makeKeyframe(TimeNs t_ns, const SE3& T_w_c, const FrameFeatures& f, const Matches& m) {
  std::lock_guard<std::mutex> lock(map_->mutex());
  KeyFrame kf;
  kf.t_ns = t_ns;
  kf.T_w_c = T_w_c;
  kf.features = f;
  const Id id = map_->addKeyFrame(std::move(kf));
  int tracked = 0, created = 0;
  for (size_t i = 0; i < m.point_ids.size(); ++i) {
    if (m.point_ids[i] == kNoId || !map_->point(m.point_ids[i])) continue;
    map_->addPointObservation(id, static_cast<int>(i), m.point_ids[i]);
    ++tracked;
  }
  for (size_t i = 0; i < m.line_ids.size(); ++i)
    if (m.line_ids[i] != kNoId && map_->line(m.line_ids[i])) map_->addLineObservation(id, static_cast<int>(i), m.line_ids[i]);
  // New map points straight from depth (RGB-D), so the next frames can track them even
  // before the local mapper has processed this keyframe.
  for (size_t i = 0; i < f.points.size(); ++i) {
    const Keypoint& k = f.points[i];
    if (m.point_ids.size() > i && m.point_ids[i] != kNoId) continue;
    if (!(std::isfinite(k.depth_m) && k.depth_m > 0 && k.depth_m < options_.max_depth_m)) continue;
    MapPoint p;
    p.p_w = T_w_c * camera_.unprojectIdeal(k.uv, k.depth_m);
    p.descriptor = f.point_descriptors.row(static_cast<int>(i)).clone();
    p.first_keyframe = id;
    const Id pid = map_->addPoint(std::move(p));
    map_->addPointObservation(id, static_cast<int>(i), pid);
    ++created;
  }
  if (places_.enabled()) places_.add(id, frameWords(f));  // computed once if a fallback already needed them
  reference_kf_ = id;
  // What later frames are compared with: the landmarks this keyframe was tracked with
  // (the first keyframe has only the ones it created).
  reference_kf_landmarks_ = tracked > 0 ? tracked : created;
  keyframe_landmarks_[id] = reference_kf_landmarks_;
  frames_since_kf_ = 0;
  return id;
}

}  // namespace plslam
