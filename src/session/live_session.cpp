#include "session/live_session.h"

#include <chrono>

#include "core/error.h"
#include "core/log.h"
#include "core/profile.h"
#include "dense/dense_products.h"
#include "system/run_outputs.h"

namespace plslam {

namespace {
const Logger kLog("session");
}  // namespace

SparseMapSnapshot sparseMapSnapshot(const Map& map) {
  SparseMapSnapshot out;
  std::lock_guard<std::mutex> lock(map.mutex());
  out.points.reserve(map.points().size());
  for (const auto& [id, p] : map.points()) out.points.push_back(p.p_w);
  out.lines.reserve(map.lines().size());
  for (const auto& [id, l] : map.lines()) out.lines.emplace_back(l.P_w, l.Q_w);
  return out;
}

LiveSession::LiveSession(const PinholeCamera& camera, RunConfig config, SessionOptions options)
    : camera_(camera),
      options_(std::move(config.options)),
      session_options_(std::move(options)),
      config_yaml_(std::move(config.config_yaml)),
      queue_(session_options_.queue, session_options_.drop_frames ? QueuePolicy::kDropOldest : QueuePolicy::kBlock),
      map_frame_keyframes_(session_options_.map_frame_keyframes) {
  localizing_ = options_.tracker.localization_only;
  // A saved map keeps its own frame, so that its sessions share one map frame.
  if (config.map && config.map->frame) map_frame_ = config.map->frame;
  makeSystem(config.map ? std::move(config.map->map) : Map(), map_frame_ ? &*map_frame_ : nullptr);
}

void LiveSession::makeSystem(Map map, const MapFrame* given) {
  auto system = std::make_shared<System>(camera_, options_, std::move(map));
  corrections_seen_ = system->map().corrections();  // a loaded map's own corrections are no news
  maps_ = session_options_.live_maps ? makeLiveMaps(system.get(), session_options_.maps_dir, given) : nullptr;
  std::lock_guard<std::mutex> lock(system_mutex_);
  system_ = std::move(system);
}

std::shared_ptr<System> LiveSession::currentSystem() const {
  std::lock_guard<std::mutex> lock(system_mutex_);
  return system_;
}

LiveSession::~LiveSession() {
  // An owner that did not stop (an exception on its side): end the thread, keep quiet.
  queue_.close();
  if (thread_.joinable()) thread_.join();
}

void LiveSession::start() {
  if (started_) throw Error("LiveSession::start called twice");
  started_ = true;
  startPipeline();
  thread_ = std::thread([this] { slamLoop(); });
}

void LiveSession::startPipeline() {
  if (maps_) maps_->setListener(maps_listener_);
  system_->start();
  if (maps_) maps_->start();
}

void LiveSession::reset() {
  std::lock_guard<std::mutex> lock(feed_mutex_);
  if (!started_ || stopped_) throw Error("LiveSession::reset: the session is not running");
  // The old maps read the old System's map: they go first.
  if (maps_) maps_->stop();
  maps_.reset();
  try {
    system_->finish();
  } catch (const std::exception& e) {
    kLog.warn(str("reset: the dropped map's pipeline had failed: ", e.what()));  // dropped anyway
  }
  // A new map cannot be localised in: the new System maps.
  options_.tracker.localization_only = false;
  localizing_ = false;
  {
    std::lock_guard<std::mutex> frame_lock(frame_mutex_);
    map_frame_.reset();
  }
  makeSystem(Map(), nullptr);
  startPipeline();
  keyframes_ = 0;
  ++resets_;
  kLog.info(str("reset ", resets_, ": map dropped, the next frame starts a new one"));
}

bool LiveSession::push(RgbdFrame frame) {
  if (!queue_.push(std::move(frame))) return false;
  ++received_;
  return true;
}

void LiveSession::slamLoop() {
  try {
    while (auto frame = queue_.pop()) {
      FrameOutcome out;
      {
        std::lock_guard<std::mutex> lock(feed_mutex_);
        const auto t0 = std::chrono::steady_clock::now();
        const TrackingResult r = system_->feed(*frame);
        out.tracking_ms = msSince(t0);
        describe(*frame, r, &out);
      }
      if (listener_) listener_(out);
      // Counted once the listener has the outcome: whoever waits on counts() sees its effects.
      tracked_ += out.tracked;
      ++processed_;
    }
  } catch (...) {
    // The System (or the listener) failed: stop taking frames; stop() rethrows.
    failure_ = std::current_exception();
    queue_.close();
  }
}

std::optional<MapFrame> LiveSession::mapFrame() const {
  std::lock_guard<std::mutex> lock(frame_mutex_);
  return map_frame_;
}

MapFrame LiveSession::fixMapFrame() {
  if (const auto frame = mapFrame()) return *frame;
  // The dense floor of the maps while running when they found it (a better floor than the
  // few map points of the first keyframes: 0.59 m apart once on the synthetic static scene).
  const std::optional<MapFrame> settled = maps_ ? maps_->settledFrame() : std::nullopt;
  const MapFrame frame = settled ? *settled : sparseMapFrame(*system_);
  kLog.info(str("map frame fixed from the ", settled ? "dense cloud" : "map points", " (", frame.floor_method,
                ", origin below the ", frame.origin, "): first camera ", frame.cameraHeight(), " m above the floor"));
  std::lock_guard<std::mutex> lock(frame_mutex_);
  map_frame_ = frame;
  return frame;
}

void LiveSession::describe(const RgbdFrame& frame, const TrackingResult& r, FrameOutcome* out) {
  out->t_ns = frame.t_ns;
  out->status = r.status;
  out->reason = r.reason;
  out->tracked = isTracked(r.status);
  out->T_w_c = r.T_w_c;
  keyframes_ += r.new_keyframe;
  out->keyframes = keyframes_;
  out->resets = resets_;
  out->localizing = localizing_;
  if (!mapFrame() && (maps_ ? maps_->settledFrame().has_value() : keyframes_ >= map_frame_keyframes_)) fixMapFrame();
  if (const auto fixed = mapFrame()) {
    out->map_frame_fixed = true;
    out->T_map_world = fixed->T_map_world;
  }
  uint64_t corrections = 0;
  {
    std::lock_guard<std::mutex> lock(system_->map().mutex());
    corrections = system_->map().corrections();
  }
  if (corrections == corrections_seen_) return;
  corrections_seen_ = corrections;
  // Between two frames on the feeding thread: the records are this thread's, the map locked.
  out->revised = std::make_shared<const Trajectory>(system_->trajectory());
}

void LiveSession::save(const std::string& dir, const Json& stats_extra) {
  std::lock_guard<std::mutex> lock(feed_mutex_);
  const MapFrame frame = fixMapFrame();  // what is saved and what is published from now on agree
  writeRunOutputs(dir, *system_, config_yaml_, stats_extra, "", &frame);
}

void LiveSession::setLocalization(bool on) {
  std::lock_guard<std::mutex> lock(feed_mutex_);
  if (stopped_) throw Error("LiveSession::setLocalization: the session has stopped");
  system_->setLocalizationOnly(on);
  localizing_ = on;
}

SessionCounts LiveSession::counts() const {
  SessionCounts c;
  c.received = received_;
  c.processed = processed_;
  c.tracked = tracked_;
  c.dropped = static_cast<int>(queue_.dropped());
  return c;
}

void LiveSession::stop() {
  if (stopped_ || !started_) return;
  {
    std::lock_guard<std::mutex> lock(feed_mutex_);  // no reset() from here on
    stopped_ = true;
  }
  queue_.close();
  thread_.join();
  if (failure_) std::rethrow_exception(failure_);
  // No map update races the end: the final products are built from the final poses.
  if (maps_) maps_->stop();
  system_->finish();
  const SessionCounts c = counts();
  kLog.info(str("received ", c.received, ", processed ", c.processed, ", dropped ", c.dropped, ", tracked ",
                c.tracked));
}

void LiveSession::writeOutputs(const std::string& dir, const Json& stats_extra, bool dense) {
  if (!stopped_) throw Error("LiveSession::writeOutputs before stop()");
  Json extra = stats_extra.is_null() ? Json::object() : stats_extra;
  if (maps_) extra.update(liveMapsStatsJson(maps_->stats()));
  // The dense products first: the floor of their cloud gives the map frame of every output,
  // as in plslam run (without them the run outputs find the floor in the sparse map).
  // A fixed map frame (the one published) is kept for every output.
  const System& system = *system_;
  const DenseOptions& dopt = system.options().dense;
  const std::optional<MapFrame> fixed = mapFrame();
  if (!dense || !dopt.enabled) {
    writeRunOutputs(dir, system, config_yaml_, extra, "", fixed ? &*fixed : nullptr);
    return;
  }
  const DenseProducts products = buildDenseProducts(system.map(), system.camera(), dopt, {}, {}, fixed ? &*fixed : nullptr);
  writeDenseProducts(dir, products, {}, dopt);
  writeRunOutputs(dir, system, config_yaml_, extra, "", &products.frame);
}

}  // namespace plslam
