#include "system/system.h"

#include <chrono>
#include <thread>

#include "core/profile.h"
#include "core/bounded_queue.h"
#include "core/error.h"
#include "core/log.h"
#include "core/thread_priority.h"
#include "core/worker_thread.h"
#include "dense/keyframe_cloud.h"
#include "dynamic/semantic_labels.h"
#include "place/vocabulary.h"

namespace plslam {

namespace {
const Logger kLog("system");

/// The vocabulary of loop closure and relocalisation. Loop closure cannot work without it
/// (ConfigError); tracking can, with brute-force relocalisation over recent keyframes only.
std::shared_ptr<const VocabularySet> placeVocabulary(const std::string& path, bool required) {
  const std::string file = path.empty() ? defaultVocabularyPath() : path;
  try {
    return std::make_shared<const VocabularySet>(loadVocabulary(file));
  } catch (const Error& e) {
    if (required)
      throw ConfigError(str("loop closure: cannot use the vocabulary (loop.vocabulary, or --no-loop): ", e.what()));
    kLog.warn(str("no vocabulary (", e.what(), "): relocalisation tries the recent keyframes only"));
    return nullptr;
  }
}

}  // namespace

struct System::Pipeline {
  /// What the mapping thread gets of a new keyframe's frame.
  struct KeyframeJob {
    Id keyframe;
    // A queued job owns its pixels (deep copies): the mapping thread must not share buffers
    // with the caller, who may reuse them (see deepCopy in core/frame.h).
    cv::Mat depth_m;
    cv::Mat bgr;
    cv::Mat dynamic_mask;  ///< CV_8U, 0 = moving objects (empty: no filtering)
    cv::Mat classes;       ///< classImage() of the frame's masks (empty without a segmenter)
  };
  Pipeline(Map* map, const PinholeCamera& camera, const SystemOptions& o, std::shared_ptr<const VocabularySet> vocabulary)
      : tracker(map, camera, o.tracker, vocabulary),
        mapper(map, camera, o.mapper),
        dynamic(camera, o.dynamic, o.dynamic.enabled ? makeSegmenter(o.segmenter) : nullptr, !o.sequential),
        queue(o.mapping_queue, QueuePolicy::kBlock),
        // Unbounded in practice: every keyframe must reach the loop closer's database, and it
        // gets a few a second at most; a correction's solves may hold the loop thread a while.
        loop_queue(1 << 16, QueuePolicy::kBlock),
        map(map),
        camera(camera),
        dense(o.dense),
        sequential(o.sequential) {}
  /// The mapping thread's work on one keyframe (on the caller's thread when sequential).
  void processKeyframe(const KeyframeJob& job) {
    if (dense.enabled) {
      // The cloud is made outside the lock (a few ms) and stored under it.
      std::vector<DensePoint> cloud =
          makeKeyframeCloud(camera, job.bgr, job.depth_m, job.dynamic_mask, job.classes, dense);
      std::lock_guard<std::mutex> lock(map->mutex());
      if (KeyFrame* kf = map->keyframe(job.keyframe)) kf->dense = std::move(cloud);
    }
    mapper.processKeyframe(job.keyframe, job.depth_m);
    if (loop) {
      if (sequential) loop->processKeyframe(job.keyframe);
      else loop_queue.push(job.keyframe);  // the loop thread: local mapping never waits for a loop search
    }
    if (keyframe_observer) keyframe_observer(job.keyframe);
  }
  /// A worker's exception: the first one is kept, and the queues close so that every thread
  /// stops instead of waiting on a stage that is gone; feed() and finish() rethrow it.
  void fail(const char* stage, const std::exception& e) {
    {
      std::lock_guard<std::mutex> lock(failure_mutex);
      if (failure.empty()) failure = str(stage, " thread failed: ", e.what(), "; the pipeline stopped");
    }
    kLog.error(str(stage, " thread failed: ", e.what()));
    queue.close();
    loop_queue.close();
  }
  void rethrowFailure() {
    std::lock_guard<std::mutex> lock(failure_mutex);
    if (!failure.empty()) throw Error(failure);
  }
  Tracker tracker;
  LocalMapper mapper;
  DynamicFilter dynamic;
  /// Each frame's segments, beside its keypoints: one thread for the whole run rather than
  /// one per frame (docs/RESULTS.md, "One thread for the segments, kept").
  std::unique_ptr<WorkerThread> line_worker;
  BoundedQueue<KeyframeJob> queue;
  BoundedQueue<Id> loop_queue;   ///< keyframes the mapper finished, for the loop thread
  Map* map;                      ///< for storing the dense clouds
  PinholeCamera camera;
  DenseOptions dense;            ///< per-keyframe dense clouds
  bool sequential;               ///< the loop closer runs inline after the mapper
  std::thread mapping_thread;
  std::thread loop_thread;        ///< place recognition and corrections (threaded mode with loop closure)
  bool started = false, finished = false;
  std::unique_ptr<LoopCloser> loop;  ///< null without loop closure
  std::mutex tracking_mutex;         ///< held while a frame is tracked; loop corrections wait for it
  std::function<void(Id)> keyframe_observer;  ///< see System::setKeyframeObserver
  std::mutex failure_mutex;
  std::string failure;               ///< the first worker failure (empty: none)
};

System::System(PinholeCamera camera, SystemOptions options) : System(std::move(camera), std::move(options), Map()) {}

System::System(PinholeCamera camera, SystemOptions options, Map map)
    : camera_(std::move(camera)), options_(std::move(options)), map_(std::move(map)) {
  if (options_.background_nice < 0 || options_.background_nice > 19)
    throw ConfigError(str("system.background_nice must be in 0..19 (got ", options_.background_nice, ")"));
  if (options_.refine_after_keyframes < 0 || options_.refine_after_frames < 0)
    throw ConfigError(str("system.refine_after_keyframes and system.refine_after_frames must be >= 0 (got ",
                          options_.refine_after_keyframes, " and ", options_.refine_after_frames, ")"));
  validateDepthCorrection(options_.depth_correction);
  options_.tracker.use_lines = options_.use_lines;
  options_.mapper.use_lines = options_.use_lines;
  options_.features.use_lines = options_.use_lines;
  // The solvers' pixel sigma grows with the pyramid level the keypoints come from (the float
  // field cannot hold 1.2 exactly: the double is kept when it is the same number as a float).
  for (MeasurementModel* model : {&options_.tracker.optimizer.model, &options_.mapper.ba.model, &options_.loop.ba.model})
    if (static_cast<float>(model->scale_factor) != options_.features.orb.scale_factor)
      model->scale_factor = options_.features.orb.scale_factor;
  const bool use_loop = options_.use_loop && !options_.tracker.localization_only;
  const std::shared_ptr<const VocabularySet> vocabulary = placeVocabulary(options_.loop.vocabulary, use_loop);
  pipeline_ = std::make_unique<Pipeline>(&map_, camera_, options_, vocabulary);
  if (use_loop) {
    Pipeline* p = pipeline_.get();
    p->loop = std::make_unique<LoopCloser>(&map_, camera_, options_.loop, vocabulary);
    p->loop->setCorrectionHook(&p->tracking_mutex, [p](const LoopCorrection& c) { p->tracker.applyMapCorrection(c.T_new_old); });
    // A loaded map's places can be recognised when this session comes back to them.
    if (const int n = p->loop->indexMapKeyframes()) kLog.info(str("loop: ", n, " keyframes of the loaded map indexed"));
  }
}

System::~System() {
  if (!pipeline_ || !pipeline_->started || pipeline_->finished) return;
  try {
    finish();
  } catch (const std::exception& e) {
    kLog.error(str("System destroyed unfinished: ", e.what()));
  }
}

void System::start() {
  if (pipeline_->started) return;
  pipeline_->started = true;
  pipeline_->line_worker = std::make_unique<WorkerThread>("plslam-lines");
  if (options_.sequential) return;
  const int nice = options_.background_nice;
  pipeline_->mapping_thread = std::thread([p = pipeline_.get(), nice] {
    if (!setThisThreadNice(nice)) kLog.debug("mapping thread: the scheduler refused system.background_nice");
    try {
      while (auto job = p->queue.pop()) p->processKeyframe(*job);
    } catch (const std::exception& e) {
      p->fail("mapping", e);
    }
    p->loop_queue.close();  // the loop thread finishes what the mapper handed it
  });
  if (pipeline_->loop)
    pipeline_->loop_thread = std::thread([p = pipeline_.get(), nice] {
      if (!setThisThreadNice(nice)) kLog.debug("loop thread: the scheduler refused system.background_nice");
      try {
        while (auto id = p->loop_queue.pop()) p->loop->processKeyframe(*id);
      } catch (const std::exception& e) {
        p->fail("loop closure", e);
      }
    });
}

TrackingResult System::feed(const RgbdFrame& input, const cv::Mat& mask) {
  // The depth correction first, so that tracking, mapping and the dense clouds all see it.
  RgbdFrame frame = input;
  frame.depth_m = correctDepth(input.depth_m, options_.depth_correction);
  if (!pipeline_->started) start();
  if (pipeline_->finished) throw Error("System::feed after finish()");
  pipeline_->rethrowFailure();
  const auto t0 = std::chrono::steady_clock::now();
  FrameRecord rec;
  rec.t_ns = frame.t_ns;
  // The dynamic check needs only the keypoints: it runs while the other thread extracts
  // the segments, which are filtered with its mask once they are there.
  FeatureExtraction extraction(frame, mask, camera_, options_.features, pipeline_->line_worker.get());
  FrameFeatures f = extraction.points(&rec.stages);
  DynamicFrameResult dyn;
  {
    const StageTimer timer(&rec.stages, Stage::kDynamic);
    dyn = pipeline_->dynamic.process(frame, &f, pipeline_->tracker.predictedMotion());
  }
  extraction.addLines(&f, &rec.stages);
  pipeline_->dynamic.removeLines(&f, &dyn);
  rec.features_ms = msSince(t0);
  rec.dynamic_points_rejected = dyn.points_rejected;
  rec.dynamic_lines_rejected = dyn.lines_rejected;
  rec.segmentation_ms = dyn.segmentation_ms;
  rec.fresh_segmentation = dyn.fresh_segmentation;
  rec.mask_age_frames = dyn.mask_age_frames;
  std::unique_lock<std::mutex> tracking(pipeline_->tracking_mutex);  // no loop correction from here to the record
  const TrackingResult r = pipeline_->tracker.track(frame.t_ns, f);
  rec.tracking_ms = msSince(t0);
  rec.stages.add(r.times);
  rec.status = r.status;
  rec.method = r.method;
  rec.points = static_cast<int>(f.points.size());
  rec.lines = static_cast<int>(f.lines.size());
  rec.matched_points = r.matched_points;
  rec.matched_lines = r.matched_lines;
  rec.local_points = r.local_points;
  rec.local_lines = r.local_lines;
  if (isTracked(r.status)) {
    std::lock_guard<std::mutex> lock(map_.mutex());
    if (r.new_keyframe) {
      KeyFrame* kf = map_.keyframe(r.keyframe_id);
      kf->dynamic_mask = dyn.mask;
      kf->instances = describeInstances(dyn.segmentation, dyn.decisions, frame.depth_m, camera_);
    }
    rec.reference_keyframe = r.reference_keyframe;
    rec.T_ref_c = map_.keyframe(r.reference_keyframe)->T_w_c.inverse() * r.T_w_c;
  }
  rec.keyframes_before = keyframes_made_;
  if (options_.refine_frames && !r.point_matches.empty()) rec.observations = matchedObservations(f, r.point_matches, r.line_matches);
  records_.push_back(std::move(rec));
  tracking.unlock();
  keyframes_made_ += r.new_keyframe;
  // Two a frame (about 1 ms each): the backlog a keyframe settles is worked off over the
  // next frames instead of in one burst that would delay the next pose.
  if (options_.refine_frames) {
    const auto t_refine = std::chrono::steady_clock::now();
    refineSettledFrames(options_.refine_after_keyframes, options_.refine_after_frames, 2);
    records_.back().refinement_ms = msSince(t_refine);
  }
  if (r.new_keyframe) {
    // The class image is only read for the dense cloud; it is a new image, owned by the job.
    cv::Mat classes = pipeline_->dense.enabled ? classImage(dyn.segmentation) : cv::Mat();
    if (options_.sequential)
      pipeline_->processKeyframe({r.keyframe_id, frame.depth_m, frame.bgr, dyn.mask, std::move(classes)});
    else if (!pipeline_->queue.push(  // the mapping thread gets its own pixels (see KeyframeJob)
                 {r.keyframe_id, frame.depth_m.clone(), frame.bgr.clone(), dyn.mask.clone(), std::move(classes)}))
      pipeline_->rethrowFailure();  // closed: the mapping thread stopped
  }
  return r;
}

void System::finish() {
  if (!pipeline_->started) return;
  if (pipeline_->finished) return pipeline_->rethrowFailure();
  pipeline_->finished = true;
  pipeline_->queue.close();
  if (pipeline_->mapping_thread.joinable()) pipeline_->mapping_thread.join();
  if (pipeline_->loop_thread.joinable()) pipeline_->loop_thread.join();
  if (options_.refine_frames) refineSettledFrames(0, 0, records_.size());
  pipeline_->rethrowFailure();
}

void System::setLocalizationOnly(bool on) {
  options_.tracker.localization_only = on;
  pipeline_->tracker.setLocalizationOnly(on);
  kLog.info(on ? "localisation only: the map is kept as it is" : "mapping again");
}

void System::setKeyframeObserver(std::function<void(Id)> observer) {
  if (pipeline_->started) throw Error("System::setKeyframeObserver after start()");
  pipeline_->keyframe_observer = std::move(observer);
}

void System::refineSettledFrames(int after_keyframes, int after_frames, size_t max_frames) {
  const PoseOptimizer optimizer(options_.tracker.optimizer);
  for (size_t done = 0; next_to_refine_ < records_.size() && done < max_frames; ++next_to_refine_) {
    FrameRecord& rec = records_[next_to_refine_];
    const bool settled = keyframes_made_ - rec.keyframes_before >= after_keyframes ||
                         records_.size() - next_to_refine_ > static_cast<size_t>(after_frames);
    if (!settled) break;
    if (rec.observations.empty() || rec.reference_keyframe == kNoId) continue;
    PoseOnlyProblem problem;
    std::optional<SE3> T_w_ref;
    {
      std::lock_guard<std::mutex> lock(map_.mutex());
      if (const KeyFrame* kf = map_.keyframe(rec.reference_keyframe)) {
        T_w_ref = kf->T_w_c;
        problem = poseProblem(map_, &rec.observations, *T_w_ref * rec.T_ref_c);
      }
    }
    rec.observations = FrameObservations();
    if (!T_w_ref) continue;
    ++done;
    // Solved without the lock; kept relative to the keyframe pose it started from, so a loop
    // correction meanwhile carries over.
    if (const auto T_w_c = solveRefinement(camera_, optimizer, problem, options_.tracker.min_inliers)) {
      rec.T_ref_c = T_w_ref->inverse() * *T_w_c;
      rec.refined = true;
    }
  }
}

const LoopCloser* System::loopCloser() const { return pipeline_->loop.get(); }

Trajectory System::trajectory() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  Trajectory out;
  for (const FrameRecord& r : records_) {
    if (r.reference_keyframe == kNoId) continue;
    const KeyFrame* kf = map_.keyframe(r.reference_keyframe);
    if (kf) out.push_back({r.t_ns, kf->T_w_c * r.T_ref_c});
  }
  return out;
}

Trajectory System::keyframeTrajectory() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  Trajectory out;
  for (const auto& [id, kf] : map_.keyframes()) out.push_back({kf.t_ns, kf.T_w_c});
  return out;
}

namespace {
/// Each loss that ended (relocalised or re-anchored): frames from the first lost frame to the
/// tracked one, and the time between their stamps. Losses still open at the end count
/// in lost_events only.
void addRecoveries(const std::vector<FrameRecord>& records, RunStats* s) {
  const FrameRecord* first_lost = nullptr;
  int lost_frames = 0;
  for (const FrameRecord& r : records) {
    const bool tracked = isTracked(r.status);
    if (!tracked && r.status != TrackingStatus::kNotInitialized) {
      if (!first_lost) first_lost = &r;
      ++lost_frames;
    } else if (tracked && first_lost) {
      s->recovery_frames.push_back(lost_frames);
      s->recovery_s.push_back(nsToSeconds(r.t_ns - first_lost->t_ns));
      first_lost = nullptr;
      lost_frames = 0;
    }
  }
}
}  // namespace

int System::keyframeCount() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return static_cast<int>(map_.keyframes().size());
}

RunStats System::stats() const {
  RunStats s;
  s.frames = static_cast<int>(records_.size());
  for (const FrameRecord& r : records_) {
    s.tracked += isTracked(r.status);
    s.tracking_ms.push_back(r.tracking_ms);
    s.features_ms.push_back(r.features_ms);
    s.dynamic_points_rejected.push_back(r.dynamic_points_rejected);
    if (r.segmentation_ms >= 0) s.segmentation_ms.push_back(r.segmentation_ms);
    s.fresh_segmentations += r.fresh_segmentation;
    if (r.mask_age_frames >= 0) s.mask_age_frames.push_back(r.mask_age_frames);
    s.refined_frames += r.refined;
    s.refinement_ms.push_back(r.refinement_ms);
    for (int i = 0; i < kStageCount; ++i) s.stage_ms[i].push_back(r.stages.ms[i]);
    ++s.methods[static_cast<int>(r.method)];
  }
  addRecoveries(records_, &s);
  s.lost_events = pipeline_->tracker.lostEvents();
  s.relocalisations = pipeline_->tracker.relocalisations();
  s.reanchors = pipeline_->tracker.reanchors();
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    s.keyframes = static_cast<int>(map_.keyframes().size());
    s.map_points = static_cast<int>(map_.points().size());
    s.map_lines = static_cast<int>(map_.lines().size());
  }
  const MapperStats m = pipeline_->mapper.stats();
  s.line_rate_fitting = m.rate_fitting.average();
  s.line_rate_endpoints = m.rate_endpoints.average();
  s.line_rate_keyframes = m.rate_fitting.frames();
  s.ba_ms = m.ba_ms;
  s.use_lines = options_.use_lines;
  s.sequential = options_.sequential;
  s.use_dynamic = options_.dynamic.enabled;
  s.segmenter = options_.dynamic.enabled ? segmenterKindName(options_.segmenter.kind) : "off";
  s.use_loop = pipeline_->loop != nullptr;
  if (pipeline_->loop) s.loop = pipeline_->loop->stats();
  return s;
}

}  // namespace plslam
