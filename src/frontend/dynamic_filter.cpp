#include "frontend/dynamic_filter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/profile.h"
#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"
#include "features/matching.h"

namespace plslam {

namespace {
const Logger kLog("dynamic");


bool dynamicAt(const cv::Mat& mask, const Eigen::Vector2d& uv) {
  const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
  return u >= 0 && v >= 0 && u < mask.cols && v < mask.rows && mask.at<uint8_t>(v, u) == 0;
}
}  // namespace

std::vector<uint8_t> removeDynamicPoints(FrameFeatures* f, const cv::Mat& mask, const std::vector<uint8_t>& point_dynamic) {
  std::vector<Keypoint> points;
  cv::Mat point_desc(0, 32, CV_8U);
  std::vector<uint8_t> kept(f->points.size(), 0);
  for (size_t i = 0; i < f->points.size(); ++i) {
    const bool flagged = i < point_dynamic.size() && point_dynamic[i];
    if (flagged || (!mask.empty() && dynamicAt(mask, f->points[i].uv_raw))) continue;
    kept[i] = 1;
    points.push_back(f->points[i]);
    point_desc.push_back(f->point_descriptors.row(static_cast<int>(i)));
  }
  f->points = std::move(points);
  f->point_descriptors = point_desc;
  return kept;
}

int removeDynamicLines(FrameFeatures* f, const cv::Mat& mask, double line_fraction) {
  if (mask.empty()) return 0;
  std::vector<Segment2D> lines;
  cv::Mat line_desc(0, 32, CV_8U);
  int removed = 0;
  for (size_t i = 0; i < f->lines.size(); ++i) {
    const Segment2D& s = f->lines[i];
    int on_dynamic = 0;
    const int samples = 11;
    for (int k = 0; k < samples; ++k)
      on_dynamic += dynamicAt(mask, s.p_raw + (s.q_raw - s.p_raw) * (k / double(samples - 1)));
    if (on_dynamic > line_fraction * samples) {
      ++removed;
      continue;
    }
    lines.push_back(s);
    line_desc.push_back(f->line_descriptors.row(static_cast<int>(i)));
  }
  f->lines = std::move(lines);
  f->line_descriptors = line_desc;
  return removed;
}

void DynamicFilter::removeLines(FrameFeatures* f, DynamicFrameResult* r) const {
  if (!options_.enabled) return;
  r->lines_rejected += removeDynamicLines(f, r->mask, options_.line_masked_fraction);
}

void DynamicFilterOptions::validate() const {
  auto require = [](bool ok, const char* key, const std::string& range, double value) {
    requireOption(ok, "dynamic", key, range, value);
  };
  require(segment_every >= 1, "segment_every", ">= 1", segment_every);
  require(compare_gap >= 1, "compare_gap", ">= 1", compare_gap);
  require(match_radius_px > 0, "match_radius_px", "> 0", match_radius_px);
  require(predicted_search_px >= 0, "predicted_search_px", ">= 0", predicted_search_px);
  require(unmatched_search_px >= 0, "unmatched_search_px", ">= 0", unmatched_search_px);
  require(predicted_search_support >= 1, "predicted_search_support", ">= 1", predicted_search_support);
  require(match_ratio > 0 && match_ratio <= 1, "match_ratio", "in (0, 1]", match_ratio);
  require(match_max_distance >= 0 && match_max_distance <= 256, "match_max_distance", "in [0, 256]", match_max_distance);
  require(line_masked_fraction >= 0 && line_masked_fraction <= 1, "line_masked_fraction", "in [0, 1]",
          line_masked_fraction);
  require(spread.min_still_neighbours >= 0, "spread_min_still_neighbours", ">= 0", spread.min_still_neighbours);
  require(spread.passes >= 0, "spread_passes", ">= 0", spread.passes);
  require(mask.moving_fraction >= 0 && mask.moving_fraction <= 1, "moving_fraction", "in [0, 1]", mask.moving_fraction);
  require(mask.min_checked_features >= 0, "min_checked_features", ">= 0", mask.min_checked_features);
  require(mask.dilate_px >= 0, "dilate_px", ">= 0", mask.dilate_px);
  require(mask.moving_area_dilate_px >= 0, "moving_area_dilate_px", ">= 0", mask.moving_area_dilate_px);
  require(latency_frames >= 0, "replay_latency_frames", ">= 0", latency_frames);
}

DynamicFilter::DynamicFilter(PinholeCamera camera, DynamicFilterOptions options, std::unique_ptr<Segmenter> segmenter,
                             bool asynchronous)
    : camera_(std::move(camera)),
      options_(options),
      segmenter_(std::move(segmenter)),
      asynchronous_(asynchronous),
      carrier_(options.propagation) {
  options_.validate();
  // The graph's edge test normalises by the same sensor noise as the check it is given.
  options_.delaunay.motion = options_.motion;
  // The "none" segmenter gives nothing: no worker, no requests, no mask ages to report.
  if (segmenter_ && segmenter_->name() == "none") segmenter_.reset();
  if (segmenter_ && asynchronous_) worker_ = std::thread([this] { workerLoop(); });
}

DynamicFilter::~DynamicFilter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  done_.notify_all();
  if (worker_.joinable()) worker_.join();
}

bool DynamicFilter::carriesMasks() const {
  // Only late masks, delivered after frames were processed without them: sequential mode
  // without a latency uses each segmented frame's own masks, and carrying them to the frames
  // in between changed nothing on the crowded scene and nominally worsened the other scenes.
  return options_.propagate_masks && (asynchronous_ || options_.latency_frames > 0);
}

DynamicFilter::Segmented DynamicFilter::segmentNow(const RgbdFrame& frame, int frame_number) {
  Segmented out;
  out.frame = frame_number;
  Segmentation s = segmenter_->segment(frame);
  // Prepared here, on the worker in the threaded mode: the tracking thread only tracks the corners.
  if (carriesMasks()) out.source = preparePropagation(std::move(s), frame.bgr, options_.propagation);
  else out.source.segmentation = std::move(s);
  return out;
}

void DynamicFilter::workerLoop() {
  for (;;) {
    std::pair<RgbdFrame, int> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !requests_.empty(); });
      if (stop_) return;
      job = std::move(requests_.front());
      requests_.pop_front();
      busy_ = true;
    }
    std::optional<Segmented> s;
    try {
      s = segmentNow(job.first, job.second);
    } catch (const std::exception& e) {
      kLog.warn(str("segmentation of t=", formatSecondsStamp(job.first.t_ns), " failed: ", e.what()));
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_ = false;
      finished_upto_ = job.second;  // failed too: a frame waiting for it must not wait forever
      if (s && !s->source.segmentation.empty()) finished_.push_back(std::move(*s));
    }
    done_.notify_all();
  }
}

int DynamicFilter::dueFrame() const {
  // The first frame waits for its own masks (once, one segmentation long): the map starts
  // from it, the geometric check has no earlier frame to judge it by, and without masks the
  // people in view would become the map's first landmarks.
  if (frame_count_ == 0) return 0;
  if (options_.latency_frames == 0) return -1;
  const int every = options_.segment_every;
  const int n = frame_count_ - options_.latency_frames;
  return n < 0 ? -1 : n / every * every;
}

std::optional<DynamicFilter::Segmented> DynamicFilter::takeDue(std::deque<Segmented>* segmented) const {
  std::optional<Segmented> newest;
  while (!segmented->empty() &&
         (segmented->front().frame == 0 || segmented->front().frame + options_.latency_frames <= frame_count_)) {
    newest = std::move(segmented->front());
    segmented->pop_front();
  }
  return newest;
}

std::optional<DynamicFilter::Segmented> DynamicFilter::segmentInline(const RgbdFrame& frame) {
  if (frame_count_ % options_.segment_every == 0) held_back_.push_back(segmentNow(frame, frame_count_));
  return takeDue(&held_back_);
}

std::optional<DynamicFilter::Segmented> DynamicFilter::segmentOnWorker(const RgbdFrame& frame) {
  const int every = options_.segment_every;
  std::unique_lock<std::mutex> lock(mutex_);
  // With a latency, the sequential mode's schedule (the same frames segmented). Without, ask as
  // soon as the worker is idle and `every` frames have passed since the last request: waiting
  // for the next multiple of `every` would add up to every-1 frames of age.
  const bool ask = options_.latency_frames > 0
                       ? frame_count_ % every == 0
                       : (last_request_frame_ < 0 || frame_count_ - last_request_frame_ >= every) && !busy_ &&
                             requests_.empty();
  if (ask) {
    requests_.emplace_back(deepCopy(frame), frame_count_);  // the worker owns its images (see deepCopy)
    last_request_frame_ = frame_count_;
    wake_.notify_one();
  }
  const int due = dueFrame();
  if (due >= 0) done_.wait(lock, [&] { return finished_upto_ >= due || stop_; });
  return takeDue(&finished_);
}

Segmentation DynamicFilter::latestSegmentation(const RgbdFrame& frame, DynamicFrameResult* r) {
  if (!segmenter_) return {};
  if (carriesMasks()) carrier_.addFrame(frame_count_, frame.bgr);
  if (std::optional<Segmented> arrived = asynchronous_ ? segmentOnWorker(frame) : segmentInline(frame)) {
    latest_ = std::move(*arrived);
    r->segmentation_ms = latest_.source.segmentation.ms;
    if (carriesMasks()) carrier_.setSource(latest_.source, latest_.frame);
  }
  if (latest_.frame < 0) return {};
  r->mask_age_frames = frame_count_ - latest_.frame;
  r->fresh_segmentation = r->mask_age_frames < options_.segment_every;
  if (r->mask_age_frames == 0 || !carriesMasks()) return latest_.source.segmentation;
  r->masks_propagated = true;
  return carrier_.carry(&r->propagation);
}

// Each keypoint of the earlier frame with a centre is searched within `radius_px` of it among
// the keypoints of `f` (positions in `grid`) not `excluded`. `centres`: one per earlier
// keypoint, NaN for none.
DynamicFilter::AdjacentMatches DynamicFilter::matchAdjacent(const FrameFeatures& before, const FrameFeatures& f,
                                                            const PointGrid& grid,
                                                            const std::vector<Eigen::Vector2d>& centres,
                                                            double radius_px, const std::vector<char>& excluded) const {
  AdjacentMatches out;
  if (f.points.empty() || before.points.empty()) return out;
  std::vector<PointPrediction> predictions;
  std::vector<int> earlier;  // per prediction
  for (size_t i = 0; i < centres.size(); ++i) {
    if (!centres[i].allFinite()) continue;
    predictions.push_back({centres[i], -1});
    earlier.push_back(static_cast<int>(i));
  }
  // The earlier frame's descriptors as they are when every keypoint is searched (the usual
  // case); only a subset is copied.
  cv::Mat descriptors = before.point_descriptors;
  if (earlier.size() < centres.size()) {
    descriptors = cv::Mat(0, 32, CV_8U);
    for (int i : earlier) descriptors.push_back(before.point_descriptors.row(i));
  }
  PointProjectionOptions po;
  po.radius_px = radius_px;
  po.max_distance = options_.match_max_distance;
  po.octave_window = -1;
  po.ratio = options_.match_ratio;
  for (const DescriptorMatch& m : matchPointsByProjection(predictions, descriptors, grid, {}, f.point_descriptors, po,
                                                          excluded)) {
    const Keypoint& a = before.points[earlier[m.query]];
    const Keypoint& b = f.points[m.train];
    MotionCorrespondence c;
    c.uv_prev = a.uv;
    c.uv_cur = b.uv;
    if (std::isfinite(a.depth_m)) c.p_prev = camera_.unprojectIdeal(a.uv, a.depth_m);
    if (std::isfinite(b.depth_m)) c.p_cur = camera_.unprojectIdeal(b.uv, b.depth_m);
    c.pixel_sigma_scale = std::pow(1.2, b.octave);
    out.corr.push_back(c);
    out.keypoint.push_back(m.train);
    out.earlier.push_back(earlier[m.query]);
  }
  return out;
}

// Where `prior` (T_cur_prev) moves each earlier keypoint: by its depth, or as a point at
// infinity (rotation only) without one. Keypoints it moves behind the camera keep their place.
std::vector<Eigen::Vector2d> DynamicFilter::predictedPositions(const FrameFeatures& before, const SE3& prior) const {
  std::vector<Eigen::Vector2d> uv;
  for (const Keypoint& k : before.points) {
    const bool has_depth = std::isfinite(k.depth_m);
    const Eigen::Vector3d p = camera_.unprojectIdeal(k.uv, has_depth ? k.depth_m : 1.0);
    const Eigen::Vector3d q = has_depth ? Eigen::Vector3d(prior * p) : Eigen::Vector3d(prior.rotation() * p);
    uv.push_back(q.z() > 1e-6 ? camera_.projectIdeal(q) : k.uv);
  }
  return uv;
}

// The check searches each earlier keypoint around where it was, so that it stays independent
// of the tracker's prediction, which walkers covering the view can bias: searching around the
// prediction alone let the crowd in on the synthetic crowded scene. When the prediction moves
// the keypoints further than `predicted_search_px` (median), fast motion has carried most of
// them out of the search window, so the check also searches around the prediction and takes
// those matches when their motion has clearly more support (`predicted_search_support` times
// the inliers): the prediction can help, not overrule. On the crowded scene a dragged tracker's
// prediction found the crowd with 1.1-1.7 times the inliers of the old positions; on the fast
// scene the prediction found 2.2-24 times (docs/RESULTS.md, "The prediction as a second
// search, taken only with twice the support").
DynamicFilter::CheckedMatches DynamicFilter::bestAdjacentMatches(const FrameFeatures& before, const FrameFeatures& f,
                                                                 const PointGrid& grid,
                                                                 const std::optional<SE3>& prior) const {
  std::vector<Eigen::Vector2d> where_they_were;
  for (const Keypoint& k : before.points) where_they_were.push_back(k.uv);
  CheckedMatches at_old;
  at_old.matches = matchAdjacent(before, f, grid, where_they_were, options_.match_radius_px);
  at_old.motion = checkMotion(at_old.matches.corr, camera_, options_.motion, prior);
  if (!prior || options_.predicted_search_px <= 0 || before.points.empty()) return at_old;

  const std::vector<Eigen::Vector2d> predicted = predictedPositions(before, *prior);
  std::vector<double> shift;
  for (size_t i = 0; i < predicted.size(); ++i) shift.push_back((predicted[i] - where_they_were[i]).norm());
  std::nth_element(shift.begin(), shift.begin() + shift.size() / 2, shift.end());
  if (shift[shift.size() / 2] <= options_.predicted_search_px) return at_old;

  CheckedMatches at_predicted;
  at_predicted.matches = matchAdjacent(before, f, grid, predicted, options_.match_radius_px);
  at_predicted.motion = checkMotion(at_predicted.matches.corr, camera_, options_.motion, prior);
  at_predicted.searched_prediction = true;
  const bool predicted_better =
      at_predicted.motion.ok() &&
      (!at_old.motion.ok() || at_predicted.motion.inliers >= options_.predicted_search_support * at_old.motion.inliers);
  return predicted_better ? at_predicted : at_old;
}

// Keypoints the search left unmatched get a verdict too: near walkers move farther between the
// two frames than the search radius, and without a verdict of their own they became landmarks
// (docs/RESULTS.md, "Why geometry alone fails in the crowd"). Once the camera motion is known,
// each unmatched earlier keypoint is searched within `unmatched_search_px` of where that motion
// puts it, and what it finds is judged by that motion: verdicts are added, the motion stays.
void DynamicFilter::judgeUnmatched(const FrameFeatures& before, const FrameFeatures& f, const PointGrid& grid,
                                   CheckedMatches* checked) const {
  AdjacentMatches& matches = checked->matches;
  MotionCheckResult& motion = checked->motion;
  std::vector<char> taken(f.points.size(), 0);
  for (int k : matches.keypoint) taken[k] = 1;
  std::vector<Eigen::Vector2d> centres = predictedPositions(before, motion.T_cur_prev);
  for (int e : matches.earlier) centres[e] = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  const AdjacentMatches late = matchAdjacent(before, f, grid, centres, options_.unmatched_search_px, taken);
  const MotionCheckResult judged =
      judgeAgainstMotion(late.corr, camera_, options_.motion, motion.T_cur_prev, motion.noise_scale);
  auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
  append(matches.corr, late.corr);
  append(matches.keypoint, late.keypoint);
  append(matches.earlier, late.earlier);
  append(motion.moving, judged.moving);
  append(motion.evidence, judged.evidence);
  append(motion.residual, judged.residual);
  append(motion.chi2, judged.chi2);
  checked->judged_late = static_cast<int>(late.corr.size());
}

DynamicFilter::CheckedMatches DynamicFilter::checkAdjacent(const FrameFeatures& before, const FrameFeatures& f,
                                                           const std::optional<SE3>& prior) const {
  std::vector<Eigen::Vector2d> uv;
  for (const Keypoint& k : f.points) uv.push_back(k.uv);
  const PointGrid grid(uv, camera_.width, camera_.height);  // one for every search
  CheckedMatches checked = bestAdjacentMatches(before, f, grid, prior);
  if (checked.motion.ok() && options_.unmatched_search_px > 0) judgeUnmatched(before, f, grid, &checked);
  return checked;
}

// Checks `f` against the oldest frame kept (compare_gap frames back once there are enough),
// with the tracker's per-frame prediction extended over that gap at constant velocity, then
// keeps `f`'s keypoints and `frame`'s depth for the frames to come.
DynamicFilter::CheckedMatches DynamicFilter::checkAgainstHistory(const RgbdFrame& frame, const FrameFeatures& f,
                                                                 const std::optional<SE3>& prior_T_cur_prev) {
  const int gap = static_cast<int>(previous_.size());
  std::optional<SE3> prior;
  if (prior_T_cur_prev) {
    prior = SE3();
    for (int i = 0; i < gap; ++i) prior = *prior_T_cur_prev * *prior;
  }
  CheckedMatches checked;
  if (!previous_.empty()) {
    checked = checkAdjacent(previous_.front().features, f, prior);
    checked.earlier_depth = previous_.front().depth_m;
  } else {
    checked.motion = checkMotion({}, camera_, options_.motion, prior);
  }
  checked.gap = gap;
  const bool keep_depth = options_.free_space.enabled && frame.depth_m.type() == CV_32FC1;
  previous_.push_back({FrameFeatures{f.points, f.point_descriptors, {}, cv::Mat()},
                       keep_depth ? frame.depth_m.clone() : cv::Mat()});
  while (static_cast<int>(previous_.size()) > options_.compare_gap) previous_.pop_front();
  return checked;
}

// Keypoints the check left unjudged that lie where the earlier frame saw empty space are
// moving (free_space_check.h), and so is the unjudged rest of their surface (the flood over
// `graph`); they are labelled so before the labels spread. Off by default:
// it helped every row measured, but on static fr1 it rejects 43 % of the keypoints (12 % off)
// (probably outlines whose depth is off look like arrivals; docs/RESULTS.md, "Free space in the
// earlier depth image").
void DynamicFilter::flagArrivals(const FrameFeatures& f, const SurfaceGraph& graph, const CheckedMatches& checked,
                                 std::vector<int8_t>* point_motion) const {
  std::vector<int> unjudged;
  std::vector<Eigen::Vector3d> points;
  for (size_t k = 0; k < f.points.size(); ++k) {
    const Keypoint& kp = f.points[k];
    if ((*point_motion)[k] >= 0 || !std::isfinite(kp.depth_m)) continue;
    unjudged.push_back(static_cast<int>(k));
    points.push_back(camera_.unprojectIdeal(kp.uv, kp.depth_m));
  }
  const std::vector<uint8_t> arrived =
      pointsInEarlierFreeSpace(points, checked.motion.T_cur_prev.inverse(), checked.earlier_depth, camera_,
                               options_.motion.noise, options_.free_space);
  std::vector<int> seeds;
  for (size_t i = 0; i < unjudged.size(); ++i)
    if (arrived[i]) {
      (*point_motion)[unjudged[i]] = 1;
      seeds.push_back(unjudged[i]);
    }
  floodMovingLabels(graph, std::move(seeds), point_motion);
}

// Per keypoint labels from the check (r->point_motion; also into `checked_labels`), flagged
// arrivals (when on), then spread over the graph of all keypoints when there are no instance
// masks: unmatched keypoints take their neighbours' verdict, isolated moving flags are
// mismatches (and are cleared in the check's verdicts too). Returns the triangles of
// keypoints left moving.
std::vector<std::array<cv::Point2f, 3>> DynamicFilter::labelKeypoints(const FrameFeatures& f, bool have_masks,
                                                                      CheckedMatches* checked, DynamicFrameResult* r,
                                                                      std::vector<int8_t>* checked_labels) const {
  const std::vector<int>& corr_keypoint = checked->matches.keypoint;
  MotionCheckResult& motion = checked->motion;
  r->point_motion.assign(f.points.size(), -1);
  if (motion.ok())
    for (size_t i = 0; i < corr_keypoint.size(); ++i)
      if (motion.evidence[i] != MotionEvidence::kNone) r->point_motion[corr_keypoint[i]] = motion.moving[i];
  *checked_labels = r->point_motion;
  const bool spread = motion.ok() && options_.spread_labels && (!have_masks || options_.spread_with_masks);
  const bool flood = motion.ok() && options_.free_space.enabled && !checked->earlier_depth.empty();
  if (!spread && !flood) return {};
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> depth;
  for (const Keypoint& k : f.points) {
    uv.push_back(k.uv);
    depth.push_back(k.depth_m);
  }
  const SurfaceGraph graph = buildSurfaceGraph(uv, depth, cv::Size(camera_.width, camera_.height), options_.spread);
  if (flood) flagArrivals(f, graph, *checked, &r->point_motion);
  if (!spread) return {};
  LabelSpreadResult spread_result = spreadMotionLabels(graph, r->point_motion, options_.spread);
  r->point_motion = std::move(spread_result.labels);
  for (size_t i = 0; i < corr_keypoint.size(); ++i)
    if (motion.moving[i] && r->point_motion[corr_keypoint[i]] == 0) motion.moving[i] = 0;
  return std::move(spread_result.moving_triangles);
}

// The check's verdicts, the Delaunay graph check, the moving triangles and the instance masks
// (carried to this frame when late) fused into one dynamic mask; its figures go into `r`.
DynamicMaskResult DynamicFilter::fuseEvidence(CheckedMatches* checked, const Segmentation& seg,
                                              const std::vector<std::array<cv::Point2f, 3>>& moving_triangles,
                                              DynamicFrameResult* r) const {
  const std::vector<MotionCorrespondence>& corr = checked->matches.corr;
  const DelaunayMotionResult delaunay = analyseDelaunayMotion(corr, camera_, options_.delaunay, &checked->motion);
  DynamicEvidence evidence;
  evidence.correspondences = &corr;
  evidence.motion = &checked->motion;
  evidence.delaunay = &delaunay;
  evidence.segmentation = seg.empty() ? nullptr : &seg;
  const cv::Mat interiors =
      r->masks_propagated ? carriedInteriors(seg, r->propagation, options_.propagation) : cv::Mat();
  if (!interiors.empty()) evidence.feature_labels = &interiors;
  evidence.moving_triangles = &moving_triangles;
  DynamicMaskResult fused = fuseDynamicMask(evidence, cv::Size(camera_.width, camera_.height), options_.mask);
  r->mask = fused.mask;
  r->instances = fused.stats.instances;
  r->instances_dynamic = fused.stats.instances_dynamic;
  r->segmentation = seg;
  r->decisions = fused.instances;
  return fused;
}

// Removes the keypoints the fusion found dynamic, those on the mask, and the unmatched ones
// (`checked_motion` -1) that label spreading made moving; then the segments on the mask.
void DynamicFilter::removeRejected(FrameFeatures* f, const CheckedMatches& checked, const DynamicMaskResult& fused,
                                   const std::vector<int8_t>& checked_motion, DynamicFrameResult* r) const {
  const std::vector<int>& corr_keypoint = checked.matches.keypoint;
  std::vector<uint8_t> point_dynamic(f->points.size(), 0);
  for (size_t i = 0; i < corr_keypoint.size(); ++i)
    if (i < fused.feature_dynamic.size() && fused.feature_dynamic[i]) point_dynamic[corr_keypoint[i]] = 1;
  for (size_t k = 0; k < point_dynamic.size(); ++k)
    if (checked_motion[k] < 0 && r->point_motion[k] == 1) point_dynamic[k] = 1;
  r->point_kept = removeDynamicPoints(f, fused.mask, point_dynamic);
  r->points_rejected = static_cast<int>(std::count(r->point_kept.begin(), r->point_kept.end(), 0));
  r->lines_rejected = removeDynamicLines(f, fused.mask, options_.line_masked_fraction);
}

void DynamicFilter::logFrame(const CheckedMatches& checked, const DynamicFrameResult& r, size_t points_left) const {
  const MotionCheckResult& motion = checked.motion;
  kLog.debug(str("frame ", frame_count_ - 1, ": ", points_left + r.points_rejected, " points, ",
                 checked.matches.corr.size(), " matched ", checked.gap, " frames back (", motion.with_depth,
                 " with depth), motion ", motionCheckStatusName(motion.status), " inliers ", motion.inliers, " moving ",
                 motion.movingCount(), motion.prior_used ? " prior" : "", motion.prior_won ? " prior_won" : "",
                 motion.prior_rejected ? " prior_rejected" : "", checked.searched_prediction ? " at_prediction" : "",
                 " judged_late ", checked.judged_late, "; rejected ", r.points_rejected, " points, ", r.lines_rejected,
                 " lines"));
}

DynamicFrameResult DynamicFilter::process(const RgbdFrame& frame, FrameFeatures* f,
                                          const std::optional<SE3>& prior_T_cur_prev) {
  DynamicFrameResult r;
  if (!options_.enabled) return r;
  const Segmentation seg = latestSegmentation(frame, &r);
  ++frame_count_;
  const auto t0 = std::chrono::steady_clock::now();
  CheckedMatches checked = checkAgainstHistory(frame, *f, prior_T_cur_prev);
  r.motion_status = checked.motion.status;
  std::vector<int8_t> checked_motion;  // the check's own labels, before spreading
  const std::vector<std::array<cv::Point2f, 3>> moving_triangles =
      labelKeypoints(*f, !seg.empty(), &checked, &r, &checked_motion);
  const DynamicMaskResult fused = fuseEvidence(&checked, seg, moving_triangles, &r);
  removeRejected(f, checked, fused, checked_motion, &r);
  r.filter_ms = msSince(t0);
  if (kLog.enabled(LogLevel::kDebug)) logFrame(checked, r, f->points.size());
  return r;
}

}  // namespace plslam
