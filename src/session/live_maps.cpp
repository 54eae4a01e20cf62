#include "session/live_maps.h"

#include <chrono>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "core/error.h"
#include "core/log.h"
#include "core/profile.h"
#include "core/thread_priority.h"
#include "system/run_outputs.h"

namespace plslam {

namespace {

const Logger kLog("live maps");

// How often the thread looks at the clock and the map's corrections counter when no
// keyframe wakes it (a loop correction alone does not).
constexpr std::chrono::milliseconds kPoll(500);

}  // namespace

Json liveMapsStatsJson(const LiveMapsStats& s) {
  const Summary u = summarize(s.update_ms), w = summarize(s.write_ms);
  return {{"live_map_updates", s.updates},
          {"live_map_refusions", s.refusions},
          {"live_map_failures", s.failures},
          {"live_map_update_ms", {{"median", u.median}, {"max", u.max}}},
          {"live_map_write_ms", {{"median", w.median}, {"max", w.max}}}};
}

LiveMaps::LiveMaps(const Map& map, const PinholeCamera& camera, const DenseOptions& options, std::string out_dir,
                   const MapFrame* given)
    : map_(map), maps_(std::make_unique<IncrementalDenseMaps>(camera, options, given)), options_(options), out_dir_(std::move(out_dir)) {
  if (given) settled_ = *given;
}

std::unique_ptr<LiveMaps> makeLiveMaps(System* system, std::string out_dir, const MapFrame* given) {
  const SystemOptions& o = system->options();
  if (!o.dense.liveMaps()) return nullptr;
  auto maps = std::make_unique<LiveMaps>(system->map(), system->camera(), o.dense, std::move(out_dir), given);
  maps->attach(system);
  return maps;
}

LiveMaps::~LiveMaps() { stop(); }

void LiveMaps::attach(System* system) {
  // The observer holds the signal, not this: the System's mapping thread may call it while
  // an owner that failed destroys this object before the System.
  system->setKeyframeObserver([signal = signal_](Id) { signal->keyframeMapped(); });
}

void LiveMaps::Signal::keyframeMapped() {
  {
    std::lock_guard<std::mutex> lock(mutex);
    ++pending;
  }
  wake.notify_one();
}

void LiveMaps::start() {
  if (started_) throw Error("LiveMaps::start called twice");
  started_ = true;
  last_update_ = std::chrono::steady_clock::now();
  thread_ = std::thread([this] { loop(); });
}

void LiveMaps::keyframeMapped() { signal_->keyframeMapped(); }

void LiveMaps::stop() {
  {
    std::lock_guard<std::mutex> lock(signal_->mutex);
    signal_->stopping = true;
  }
  signal_->wake.notify_one();
  if (thread_.joinable()) thread_.join();
  maps_.reset();
#ifdef __GLIBC__
  // glibc keeps freed heap pages (many small voxel cells) resident: hand them back, so the
  // final products do not stack on the maps' memory.
  malloc_trim(0);
#endif
}

bool LiveMaps::due() {
  if (options_.live_every_keyframes > 0 && signal_->pending >= options_.live_every_keyframes) return true;
  if (options_.live_every_s <= 0) return false;
  if (std::chrono::steady_clock::now() - last_update_ < std::chrono::duration<double>(options_.live_every_s))
    return false;
  if (signal_->pending > 0) return true;
  std::lock_guard<std::mutex> lock(map_.mutex());
  return map_.corrections() != corrections_;
}

void LiveMaps::loop() {
  if (!setThisThreadNice(options_.live_nice)) kLog.debug("the scheduler refused dense.live_nice");
  std::unique_lock<std::mutex> lock(signal_->mutex);
  while (!signal_->stopping) {
    signal_->wake.wait_for(lock, kPoll);
    if (signal_->stopping || !due()) continue;
    signal_->pending = 0;
    lock.unlock();
    runUpdate();
    lock.lock();
    last_update_ = std::chrono::steady_clock::now();
  }
}

void LiveMaps::runUpdate() {
  LiveMapsUpdate u;
  std::string steps;
  size_t points = 0;
  try {
    u.what = maps_->update(map_);
    if (!u.what.changed) return;
    const DenseProducts& p = maps_->products();
    if (!out_dir_.empty()) {
      const auto t0 = std::chrono::steady_clock::now();
      writeDenseProducts(out_dir_, p, {}, options_);
      u.write_ms = msSince(t0);
    }
    u.frame = p.frame;
    u.frame_settled = maps_->settledFrame().has_value();
    points = p.cloud.size();
    if (listener_) {  // copies the listener may keep (the products change at the next update)
      u.cloud = std::make_shared<const std::vector<FusedPoint>>(p.cloud);
      u.grid = std::make_shared<const OccupancyGrid>(p.grid);
    }
    for (const DenseCost& c : p.costs) steps += str(steps.empty() ? "" : ", ", c.step, " ", c.seconds * 1000.0, " ms");
  } catch (const std::exception& e) {
    kLog.warn(str("map update failed (the next one will be tried): ", e.what()));
    std::lock_guard<std::mutex> lock(signal_->mutex);
    ++stats_.failures;
    return;
  }
  {
    std::lock_guard<std::mutex> lock(signal_->mutex);
    corrections_ = u.what.corrections;
    u.index = ++stats_.updates;
    stats_.refusions += u.what.refused;
    stats_.update_ms.push_back(u.what.ms);
    stats_.write_ms.push_back(u.write_ms);
    if (u.frame_settled) settled_ = u.frame;
  }
  try {
    if (listener_) listener_(u);
  } catch (const std::exception& e) {
    kLog.warn(str("the maps listener failed: ", e.what()));
  }
  kLog.info(str("update ", u.index, " (", u.what.why, "): ", u.what.keyframes, " keyframes, ", points,
                " points, ", u.what.ms, " ms (", steps, ") + ", u.write_ms, " ms writing"));
}

std::optional<MapFrame> LiveMaps::settledFrame() const {
  std::lock_guard<std::mutex> lock(signal_->mutex);
  return settled_;
}

LiveMapsStats LiveMaps::stats() const {
  std::lock_guard<std::mutex> lock(signal_->mutex);
  return stats_;
}

}  // namespace plslam
