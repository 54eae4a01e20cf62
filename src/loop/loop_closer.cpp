#include "loop/loop_closer.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <set>
#include <tuple>

#include "core/profile.h"
#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"
#include "loop/map_correction.h"

namespace plslam {

namespace {
const Logger kLog("loop");

std::shared_ptr<const VocabularySet> loadOrThrow(const std::string& path) {
  const std::string file = path.empty() ? defaultVocabularyPath() : path;
  try {
    return std::make_shared<const VocabularySet>(loadVocabulary(file));
  } catch (const Error& e) {
    throw ConfigError(std::string("loop closure: cannot use the vocabulary (loop.vocabulary, or --no-loop): ") + e.what());
  }
}
}  // namespace

const char* toString(LoopStatus s) {
  switch (s) {
    case LoopStatus::kAccepted: return "accepted";
    case LoopStatus::kLowScore: return "low_score";
    case LoopStatus::kNoConsistentGroup: return "no_consistent_group";
    case LoopStatus::kTooSoonAfterLoop: return "too_soon_after_loop";
    case LoopStatus::kTooFewMatches: return "too_few_matches";
    case LoopStatus::kTooFewInliers: return "too_few_inliers";
    case LoopStatus::kRejectedBySemantics: return "rejected_by_semantics";
    case LoopStatus::kCorrectionFailed: return "correction_failed";
  }
  return "unknown";
}

double combinedScore(double orb, double lbd, bool lines_in_both, const LoopOptions& o) {
  const double wl = lines_in_both ? o.line_weight : 0.0;
  const double total = o.point_weight + wl;
  return total > 0 ? (o.point_weight * orb + wl * lbd) / total : 0.0;
}

namespace {
bool knownSegment(const FeatureGeometry* g, int i) {
  return g && i < static_cast<int>(g->lines.size()) && g->lines[i].first.allFinite() && g->lines[i].second.allFinite() &&
         (g->lines[i].first - g->lines[i].second).norm() > 1e-6;
}

/// Segment pairs that agree with T_query_candidate: per query line with a 3D segment, the
/// candidate line within the RANSAC gate with the closest LBD descriptor (at most
/// line_max_distance); each candidate line is used once.
std::vector<SegmentPair3D> associateLines(const FrameFeatures& q, const FrameFeatures& k, const FeatureGeometry* qg,
                                          const FeatureGeometry* kg, const SE3& T, const LoopOptions& o) {
  std::vector<SegmentPair3D> out;
  if (!qg || !kg || q.line_descriptors.empty() || k.line_descriptors.empty()) return out;
  std::vector<std::tuple<int, int, int>> pairs;  // distance, query, candidate
  for (int i = 0; i < q.line_descriptors.rows; ++i) {
    if (!knownSegment(qg, i) || qg->lines[i].first.z() > o.max_depth_m || qg->lines[i].second.z() > o.max_depth_m) continue;
    for (int j = 0; j < k.line_descriptors.rows; ++j) {
      if (!knownSegment(kg, j)) continue;
      const SegmentPair3D s{qg->lines[i].first, qg->lines[i].second, kg->lines[j].first, kg->lines[j].second};
      if (!segmentsAgree(s, T, o.ransac)) continue;
      const int d = hammingDistance(q.line_descriptors.ptr<uint8_t>(i), k.line_descriptors.ptr<uint8_t>(j));
      if (d <= o.line_max_distance) pairs.emplace_back(d, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::set<int> used_q, used_k;
  for (const auto& [d, i, j] : pairs) {
    if (used_q.count(i) || used_k.count(j)) continue;
    used_q.insert(i);
    used_k.insert(j);
    out.push_back({qg->lines[i].first, qg->lines[i].second, kg->lines[j].first, kg->lines[j].second});
  }
  return out;
}
}  // namespace

void verifyGeometry(const FrameFeatures& q, const FrameFeatures& k, const PinholeCamera& camera, const LoopOptions& o,
                    LoopCandidate* c, std::vector<std::pair<int, int>>* inlier_pairs, const FeatureGeometry* query_c,
                    const FeatureGeometry* candidate_c) {
  if (inlier_pairs) inlier_pairs->clear();
  auto usable = [&](const Keypoint& kp) { return std::isfinite(kp.depth_m) && kp.depth_m > 0 && kp.depth_m < o.max_depth_m; };
  std::vector<DescriptorMatch> matches;
  if (!q.point_descriptors.empty() && !k.point_descriptors.empty())
    matches = matchBruteForce(q.point_descriptors, k.point_descriptors, o.matching);
  std::vector<Eigen::Vector3d> pq, pk;
  std::vector<std::pair<int, int>> pairs;
  for (const DescriptorMatch& m : matches) {
    const Keypoint& a = q.points[m.query];
    const Keypoint& b = k.points[m.train];
    if (!usable(a) || !usable(b)) continue;
    auto position = [&](const Keypoint& kp, int i, const FeatureGeometry* known) {
      if (known && i < static_cast<int>(known->points.size()) && known->points[i].allFinite()) return known->points[i];
      return camera.unprojectIdeal(kp.uv, kp.depth_m);
    };
    pq.push_back(position(a, m.query, query_c));
    pk.push_back(position(b, m.train, candidate_c));
    pairs.emplace_back(m.query, m.train);
  }
  c->matches = static_cast<int>(pairs.size());
  if (c->matches < o.min_matches) {
    c->status = LoopStatus::kTooFewMatches;
    c->reason = str(c->matches, " ORB matches with depth < ", o.min_matches);
    return;
  }
  RigidRansacOptions ro = o.ransac;
  ro.seed = o.ransac.seed ^ (static_cast<uint64_t>(c->query) * 1000003ULL + static_cast<uint64_t>(c->candidate));
  RigidRansacResult r = ransacRigid(pq, pk, ro);
  // Lines join once the points have a pose: LBD alone matches few lines across a loop (the
  // viewpoint changes their descriptors), so each line of the query is paired with the
  // candidate line that agrees with the pose and has the closest descriptor, and the pose
  // is fitted again on points and lines together.
  std::vector<SegmentPair3D> lines;
  if (r.ok) lines = associateLines(q, k, query_c, candidate_c, r.T_a_b, o);
  if (!lines.empty()) r = ransacRigid(pq, pk, lines, ro);
  c->line_matches = static_cast<int>(lines.size());
  c->line_inliers = r.line_inlier_count;
  c->inliers = r.inlier_count;
  if (!r.ok || r.inlier_count < o.min_inliers || r.inlier_count < o.min_inlier_ratio * c->matches) {
    c->status = LoopStatus::kTooFewInliers;
    c->reason = str(r.inlier_count, " RANSAC inliers of ", c->matches, " matches (need ", o.min_inliers, " and ratio ",
                    o.min_inlier_ratio, ")");
    return;
  }
  c->T_query_candidate = r.T_a_b;
  c->status = LoopStatus::kAccepted;
  c->reason = str(r.inlier_count, " inliers of ", c->matches, " and ", r.line_inlier_count, " lines, rmse ", r.rmse_m, " m");
  if (inlier_pairs)
    for (size_t i = 0; i < pairs.size(); ++i)
      if (r.inliers[i]) inlier_pairs->push_back(pairs[i]);
}

namespace {
/// A keyframe's map points and map lines in its camera frame (NaN when none). Map lock held.
FeatureGeometry landmarksInCamera(const Map& map, const KeyFrame& kf) {
  const Eigen::Vector3d nan = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  FeatureGeometry g;
  g.points.assign(kf.point_ids.size(), nan);
  g.lines.assign(kf.line_ids.size(), {nan, nan});
  const SE3 T_c_w = kf.T_w_c.inverse();
  for (size_t i = 0; i < kf.point_ids.size(); ++i)
    if (const MapPoint* p = kf.point_ids[i] == kNoId ? nullptr : map.point(kf.point_ids[i])) g.points[i] = T_c_w * p->p_w;
  for (size_t i = 0; i < kf.line_ids.size(); ++i)
    if (const MapLine* l = kf.line_ids[i] == kNoId ? nullptr : map.line(kf.line_ids[i]))
      g.lines[i] = {T_c_w * l->P_w, T_c_w * l->Q_w};
  return g;
}
}  // namespace

LoopCloser::LoopCloser(Map* map, PinholeCamera camera, LoopOptions options)
    : LoopCloser(map, std::move(camera), options, loadOrThrow(options.vocabulary)) {}

void LoopOptions::validate() const {
  auto require = [](bool ok, const char* key, const std::string& range, double value) {
    requireOption(ok, "loop", key, range, value);
  };
  require(point_weight >= 0 && line_weight >= 0 && point_weight + line_weight > 0, "point_weight and line_weight",
          ">= 0 with a positive sum", point_weight + line_weight);
  require(min_normalised_score >= 0, "min_normalised_score", ">= 0", min_normalised_score);
  require(min_score >= 0, "min_score", ">= 0", min_score);
  require(exclude_recent >= 0, "exclude_recent", ">= 0", exclude_recent);
  require(max_candidates >= 1, "max_candidates", ">= 1", max_candidates);
  require(consistency >= 1, "consistency", ">= 1 (1: none)", consistency);
  require(min_matches >= 3, "min_matches", ">= 3 (a rigid fit needs three)", min_matches);
  require(min_inliers >= 3, "min_inliers", ">= 3", min_inliers);
  require(min_inlier_ratio >= 0 && min_inlier_ratio <= 1, "min_inlier_ratio", "in [0, 1]", min_inlier_ratio);
  require(ransac.threshold_m > 0, "ransac_threshold_m", "> 0", ransac.threshold_m);
  require(edge_sigma_trans_m > 0, "edge_sigma_trans_m", "> 0", edge_sigma_trans_m);
  require(edge_sigma_rot_deg > 0, "edge_sigma_rot_deg", "> 0", edge_sigma_rot_deg);
  require(min_keyframes_between_loops >= 0, "min_keyframes_between_loops", ">= 0", min_keyframes_between_loops);
}

LoopCloser::LoopCloser(Map* map, PinholeCamera camera, LoopOptions options,
                       std::shared_ptr<const VocabularySet> vocabulary)
    : map_(map), camera_(std::move(camera)), options_(std::move(options)), vocabulary_(std::move(vocabulary)) {
  options_.validate();
  if (!vocabulary_ || vocabulary_->orb.empty()) throw ConfigError("loop closure: empty vocabulary");
}

void LoopCloser::record(const LoopCandidate& c) {
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.candidates;
    if (c.status == LoopStatus::kAccepted) ++stats_.accepted;
    else ++stats_.refused[static_cast<int>(c.status)];
  }
  log_.push_back(c);
  kLog.debug(str("keyframe ", c.query, " candidate ", c.candidate, ": ", toString(c.status), " (score ", c.score,
                 ", normalised ", c.normalised, "; ", c.reason, ")"));
}

int LoopCloser::indexMapKeyframes() {
  std::vector<std::pair<Id, FrameFeatures>> pending;
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    for (const auto& [id, kf] : map_->keyframes())  // std::map: in id order
      if (!database_.contains(id)) pending.emplace_back(id, kf.features);
  }
  for (const auto& [id, features] : pending) index(id, describeBow(*vocabulary_, features));  // outside the lock
  return static_cast<int>(pending.size());
}

void LoopCloser::index(Id id, const KeyframeBow& bow) {
  if (!database_.contains(id)) order_.push_back(id);
  database_.add(id, bow);
}

std::optional<LoopCorrection> LoopCloser::processKeyframe(Id id) {
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.queries;
  }
  ++keyframes_since_loop_;
  LoopQuery query;
  std::vector<LoopCandidate> candidates;
  if (!scoreCandidates(id, &query, &candidates)) return std::nullopt;
  const std::vector<LoopCandidate> passed = consistentCandidates(std::move(candidates));
  return verifyAndClose(query, passed);
}

bool LoopCloser::scoreCandidates(Id id, LoopQuery* query, std::vector<LoopCandidate>* out) {
  FrameFeatures& features = query->features;
  std::vector<KeyframeInstance>& instances = query->instances;
  FeatureGeometry& query_geometry = query->geometry;
  std::vector<std::pair<Id, int>> covisible;
  // Copy what is needed under the lock; the bags are computed outside it.
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    const KeyFrame* kf = map_->keyframe(id);
    if (!kf) return false;
    features = kf->features;
    instances = kf->instances;
    covisible = map_->covisible(id, 1);
    query_geometry = landmarksInCamera(*map_, *kf);
  }
  const KeyframeBow bow = describeBow(*vocabulary_, features);
  const bool has_lines = !bow.lbd.empty();

  auto scoreWith = [&](const KeyframeBow& other, double* orb, double* lbd) {
    *orb = bowScore(bow.orb, other.orb);
    *lbd = bowScore(bow.lbd, other.lbd);
    return combinedScore(*orb, *lbd, has_lines && !other.lbd.empty(), options_);
  };
  // Normaliser: the best score against the covisible neighbours (the place as seen just now).
  double reference = 0;
  std::set<Id> excluded{id};
  for (const auto& [other, shared] : covisible) {
    if (shared >= options_.covisible_exclude_min_shared) excluded.insert(other);
    if (const KeyframeBow* b = database_.bow(other)) {
      double so, sl;
      reference = std::max(reference, scoreWith(*b, &so, &sl));
    }
  }
  for (int i = 0; i < options_.exclude_recent && i < static_cast<int>(order_.size()); ++i)
    excluded.insert(order_[order_.size() - 1 - i]);
  if (reference <= 0 && !order_.empty()) {  // no covisible neighbour in the database: the previous keyframe
    if (const KeyframeBow* b = database_.bow(order_.back())) {
      double so, sl;
      reference = scoreWith(*b, &so, &sl);
    }
  }

  std::vector<LoopCandidate>& candidates = *out;
  for (const DatabaseScore& s : database_.query(bow)) {
    if (excluded.count(s.keyframe)) continue;
    LoopCandidate c;
    c.query = id;
    c.candidate = s.keyframe;
    c.score_orb = s.orb;
    c.score_lbd = s.lbd;
    c.score = combinedScore(s.orb, s.lbd, has_lines && !database_.bow(s.keyframe)->lbd.empty(), options_);
    c.normalised = reference > 0 ? c.score / reference : 0.0;
    candidates.push_back(c);
  }
  index(id, bow);

  const double diagonal = std::hypot(camera_.width, camera_.height);
  if (options_.use_semantics && !instances.empty()) {
    std::lock_guard<std::mutex> lock(map_->mutex());
    for (LoopCandidate& c : candidates) {
      const KeyFrame* other = map_->keyframe(c.candidate);
      if (!other || other->instances.empty()) continue;
      const SemanticResult sem = matchInstances(instances, other->instances, diagonal, options_.semantic);
      c.semantic_factor = sem.factor;
      c.normalised *= sem.factor;
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const LoopCandidate& a, const LoopCandidate& b) { return a.normalised > b.normalised; });
  if (static_cast<int>(candidates.size()) > options_.max_candidates) candidates.resize(options_.max_candidates);
  return true;
}

std::vector<LoopCandidate> LoopCloser::consistentCandidates(std::vector<LoopCandidate> candidates) {
  // Consistency: a candidate's covisibility group must overlap a group of the previous keyframe.
  std::vector<Group> new_groups;
  std::vector<LoopCandidate> passed;
  for (LoopCandidate& c : candidates) {
    const bool low = c.score < options_.min_score || c.normalised < options_.min_normalised_score;
    if (low) {
      c.status = c.semantic_factor < 1 && c.normalised / c.semantic_factor >= options_.min_normalised_score
                     ? LoopStatus::kRejectedBySemantics
                     : LoopStatus::kLowScore;
      c.reason = str("score ", c.score, ", normalised ", c.normalised, " (semantic factor ", c.semantic_factor,
                     ") < ", options_.min_normalised_score);
      record(c);
      continue;
    }
    Group g;
    {
      std::lock_guard<std::mutex> lock(map_->mutex());
      g.members.push_back(c.candidate);
      for (const auto& [other, shared] : map_->covisible(c.candidate, 1)) g.members.push_back(other);
    }
    std::sort(g.members.begin(), g.members.end());
    g.count = 1;
    for (const Group& prev : groups_) {
      std::vector<Id> common;
      std::set_intersection(g.members.begin(), g.members.end(), prev.members.begin(), prev.members.end(),
                            std::back_inserter(common));
      if (!common.empty()) g.count = std::max(g.count, prev.count + 1);
    }
    new_groups.push_back(g);
    if (g.count < options_.consistency) {
      c.status = LoopStatus::kNoConsistentGroup;
      c.reason = str("seen in ", g.count, " consecutive keyframes < ", options_.consistency);
      record(c);
      continue;
    }
    passed.push_back(c);
  }
  groups_ = std::move(new_groups);
  return passed;
}

std::optional<LoopCorrection> LoopCloser::verifyAndClose(const LoopQuery& query, std::vector<LoopCandidate> passed) {
  const double diagonal = std::hypot(camera_.width, camera_.height);
  const std::vector<KeyframeInstance>& instances = query.instances;
  for (LoopCandidate& c : passed) {
    if (keyframes_since_loop_ < options_.min_keyframes_between_loops) {
      c.status = LoopStatus::kTooSoonAfterLoop;
      c.reason = str("a loop was closed ", keyframes_since_loop_, " keyframes ago");
      record(c);
      continue;
    }
    FrameFeatures other;
    std::vector<KeyframeInstance> other_instances;
    FeatureGeometry other_geometry;
    {
      std::lock_guard<std::mutex> lock(map_->mutex());
      const KeyFrame* kf = map_->keyframe(c.candidate);
      if (!kf) continue;
      other = kf->features;
      other_instances = kf->instances;
      other_geometry = landmarksInCamera(*map_, *kf);
    }
    std::vector<std::pair<int, int>> inlier_pairs;
    verifyGeometry(query.features, other, camera_, options_, &c, &inlier_pairs, &query.geometry, &other_geometry);
    if (c.status == LoopStatus::kAccepted && options_.use_semantics && !instances.empty() && !other_instances.empty()) {
      const SemanticResult sem =
          matchInstances(instances, other_instances, diagonal, options_.semantic, c.T_query_candidate);
      if (sem.refuted) {
        c.status = LoopStatus::kRejectedBySemantics;
        c.reason = str("no static instance agrees under the verified pose (", sem.static_a, " and ", sem.static_b,
                       " instances)");
      }
    }
    if (c.status != LoopStatus::kAccepted) {
      record(c);
      continue;
    }
    auto correction = correct(c, inlier_pairs);
    if (!correction) {
      c.status = LoopStatus::kCorrectionFailed;
      c.reason = "pose graph optimisation failed";
      record(c);
      continue;
    }
    record(c);
    keyframes_since_loop_ = 0;
    groups_.clear();
    return correction;
  }
  return std::nullopt;
}

std::unique_lock<std::mutex> LoopCloser::lockForCorrection() {
  return guard_ ? std::unique_lock<std::mutex>(*guard_) : std::unique_lock<std::mutex>();
}

bool LoopCloser::buildPoseGraph(const LoopCandidate& c, PoseGraphSnapshot* g) const {
  const KeyFrame* query = map_->keyframe(c.query);
  const KeyFrame* match = map_->keyframe(c.candidate);
  if (!query || !match) return false;
  std::map<Id, int> index;
  for (const auto& [id, kf] : map_->keyframes()) {
    index[id] = static_cast<int>(g->ids.size());
    g->ids.push_back(id);
    g->T_w_c.push_back(kf.T_w_c);
  }
  PoseGraphProblem& problem = g->problem;
  for (const SE3& T : g->T_w_c) problem.vertices.push_back({T, false});
  problem.vertices.front().fixed = true;
  const Eigen::Matrix<double, 6, 6> info =
      PoseGraphProblem::information(options_.edge_sigma_trans_m, options_.edge_sigma_rot_deg * M_PI / 180.0);
  auto relative = [&](int i, int j) { return problem.vertices[i].T_w_c.inverse() * problem.vertices[j].T_w_c; };
  // Consecutive keyframes that share no landmark were never measured against each other
  // (the tracker re-anchored after a long loss, tracker.h): their edge only keeps the
  // guess, so it is weak and a loop moves the whole jump there.
  const Eigen::Matrix<double, 6, 6> guess_info = info * 1e-6;
  std::set<std::pair<int, int>> linked;
  std::vector<std::vector<std::pair<Id, int>>> covisible(g->ids.size());
  for (size_t i = 0; i < g->ids.size(); ++i) covisible[i] = map_->covisible(g->ids[i], 1);
  for (size_t i = 1; i < g->ids.size(); ++i) {
    const Id previous = g->ids[i - 1];
    const bool measured = std::any_of(covisible[i].begin(), covisible[i].end(),
                                      [&](const std::pair<Id, int>& o) { return o.first == previous; });
    problem.edges.push_back({static_cast<int>(i - 1), static_cast<int>(i), relative(i - 1, i), measured ? info : guess_info});
    linked.insert({static_cast<int>(i - 1), static_cast<int>(i)});
  }
  for (size_t k = 0; k < g->ids.size(); ++k) {
    for (const auto& [other, shared] : covisible[k]) {
      const int i = static_cast<int>(k), j = index.at(other);
      if (shared < options_.covisibility_edge_min_shared || i >= j || linked.count({i, j})) continue;
      problem.edges.push_back({i, j, relative(i, j), info});
      linked.insert({i, j});
    }
  }
  for (const LoopEdge& e : loop_edges_) {
    if (!index.count(e.a) || !index.count(e.b)) continue;
    problem.edges.push_back({index[e.a], index[e.b], e.T_a_b, info});
  }
  // Initial guess: the query's covisibility group moves with the loop's correction.
  const SE3 T_w_query_corrected = match->T_w_c * c.T_query_candidate.inverse();
  g->correction = T_w_query_corrected * query->T_w_c.inverse();
  std::set<Id> group{c.query};
  for (const auto& [other, shared] : map_->covisible(c.query, 1)) group.insert(other);
  // The match's side stays where it is (the older, trusted part of the map).
  std::set<Id> match_side{c.candidate};
  for (const auto& [other, shared] : map_->covisible(c.candidate, 1)) match_side.insert(other);
  for (Id k : group)
    if (!match_side.count(k)) problem.vertices[index[k]].T_w_c = g->correction * problem.vertices[index[k]].T_w_c;
  return true;
}

std::optional<LoopCorrection> LoopCloser::correct(const LoopCandidate& c,
                                                  const std::vector<std::pair<int, int>>& inlier_pairs) {
  const auto t0 = std::chrono::steady_clock::now();
  // The pose graph is built under the map lock, solved without any lock (tracking and local
  // mapping go on), and its result applied in one short critical section.
  PoseGraphSnapshot graph;
  loop_edges_.push_back({c.query, c.candidate, c.T_query_candidate});
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    if (!buildPoseGraph(c, &graph)) {
      loop_edges_.pop_back();
      return std::nullopt;
    }
  }
  const PoseGraphResult result = PoseGraphOptimizer(options_.pose_graph).optimize(graph.problem);
  if (!result.ok()) {
    loop_edges_.pop_back();
    kLog.warn(str("loop ", c.query, " - ", c.candidate, ": pose graph failed (", toString(result.status), ")"));
    return std::nullopt;
  }

  LoopCorrection out;
  out.query = c.query;
  out.match = c.candidate;
  int fused = 0;
  {
    const auto t_hold = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> guard = lockForCorrection();
    std::lock_guard<std::mutex> lock(map_->mutex());
    out.T_new_old = keyframeChanges(*map_, graph.ids, graph.T_w_c, result.T_w_c);
    applyChanges(map_, out.T_new_old, {});
    if (options_.fuse_duplicates) fused = fuseLoopPoints(c, inlier_pairs);
    if (hook_) hook_(out);
    out.hold_ms += msSince(t_hold);
  }
  if (options_.global_ba) globalBundleAdjustment(&out);
  out.ms = msSince(t0);
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats_.correction_ms.push_back(out.ms);
    stats_.correction_hold_ms.push_back(out.hold_ms);
  }
  kLog.info(str("loop closed: keyframe ", c.query, " with ", c.candidate, " (", c.inliers, " inliers, ",
                graph.correction.translation().norm(), " m correction), ", graph.ids.size(), " keyframes, ",
                graph.problem.edges.size(), " edges, ", fused, " points fused, ", out.ms, " ms (map held ", out.hold_ms,
                " ms)"));
  return out;
}

int LoopCloser::fuseLoopPoints(const LoopCandidate& c, const std::vector<std::pair<int, int>>& inlier_pairs) {
  int fused = 0;
  for (const auto& [iq, im] : inlier_pairs) {
    const KeyFrame* query = map_->keyframe(c.query);
    const KeyFrame* match = map_->keyframe(c.candidate);
    if (!query || !match) break;
    if (iq >= static_cast<int>(query->point_ids.size()) || im >= static_cast<int>(match->point_ids.size())) continue;
    const Id pq = query->point_ids[iq], pm = match->point_ids[im];
    if (pq == kNoId || pm == kNoId || pq == pm || !map_->point(pq) || !map_->point(pm)) continue;
    map_->mergePoint(pq, pm);
    ++fused;
  }
  return fused;
}

BundleProblem LoopCloser::globalBundleProblem(std::vector<Id>* kf_ids, std::vector<Id>* point_ids) const {
  BundleProblem problem;
  std::map<Id, int> kf_index;
  for (const auto& [id, kf] : map_->keyframes()) {
    kf_index[id] = static_cast<int>(kf_ids->size());
    kf_ids->push_back(id);
    problem.keyframes.push_back({kf.T_w_c, kf_ids->size() == 1});
  }
  for (const auto& [pid, p] : map_->points()) {
    if (p.observations.size() < 2) continue;
    const int pi = static_cast<int>(point_ids->size());
    point_ids->push_back(pid);
    problem.points.push_back({p.p_w, false});
    for (const auto& [kid, idx] : p.observations) {
      const KeyFrame* kf = map_->keyframe(kid);
      if (!kf || idx < 0 || idx >= static_cast<int>(kf->features.points.size())) continue;
      const Keypoint& kp = kf->features.points[idx];
      BundleProblem::PointObs o;
      o.keyframe = kf_index.at(kid);
      o.point = pi;
      o.uv = kp.uv;
      o.octave = kp.octave;
      o.depth = std::isfinite(kp.depth_m) && kp.depth_m > 0 ? kp.depth_m : std::numeric_limits<double>::quiet_NaN();
      problem.point_obs.push_back(o);
    }
  }
  return problem;
}

void LoopCloser::globalBundleAdjustment(LoopCorrection* correction) {
  // Like the pose graph: the problem is a snapshot, solved without the lock, applied as the
  // change of each keyframe from its snapshot pose (lines and single-view points follow
  // their keyframe; map points that local BA moved meanwhile too).
  std::vector<Id> kf_ids, point_ids;
  BundleProblem problem;
  {
    std::lock_guard<std::mutex> lock(map_->mutex());
    problem = globalBundleProblem(&kf_ids, &point_ids);
  }
  const BundleResult r = BundleAdjuster(options_.ba).adjust(camera_, problem);
  if (!r.ok()) {
    kLog.warn(str("global BA after the loop failed (", toString(r.status), "); the pose-graph result is kept"));
    return;
  }
  std::vector<SE3> snapshot;
  for (const auto& k : problem.keyframes) snapshot.push_back(k.T_w_c);
  std::map<Id, std::pair<Eigen::Vector3d, Eigen::Vector3d>> solved_points;
  for (size_t i = 0; i < point_ids.size(); ++i) solved_points[point_ids[i]] = {problem.points[i].p_w, r.points[i]};
  const auto t_hold = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> guard = lockForCorrection();
  std::lock_guard<std::mutex> lock(map_->mutex());
  LoopCorrection step;
  step.T_new_old = keyframeChanges(*map_, kf_ids, snapshot, r.T_w_c);
  applyChanges(map_, step.T_new_old, solved_points);
  if (hook_) hook_(step);
  for (const auto& [id, T] : step.T_new_old) {
    auto it = correction->T_new_old.find(id);
    correction->T_new_old[id] = it == correction->T_new_old.end() ? T : T * it->second;
  }
  correction->hold_ms += msSince(t_hold);
  kLog.info(str("global BA after the loop: ", kf_ids.size(), " keyframes, ", point_ids.size(), " points, ", r.outliers,
                " outliers, ", r.time_ms, " ms"));
}

}  // namespace plslam
