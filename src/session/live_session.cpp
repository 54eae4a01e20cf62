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
    : system_(camera, config.options, config.map ? std::move(config.map->map) : Map()),
      config_yaml_(std::move(config.config_yaml)),
      queue_(options.queue, options.drop_frames ? QueuePolicy::kDropOldest : QueuePolicy::kBlock) {}

LiveSession::~LiveSession() {
  // An owner that did not stop (an exception on its side): end the thread, keep quiet.
  queue_.close();
  if (thread_.joinable()) thread_.join();
}

void LiveSession::start() {
  if (started_) throw Error("LiveSession::start called twice");
  started_ = true;
  system_.start();
  thread_ = std::thread([this] { slamLoop(); });
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
        const TrackingResult r = system_.feed(*frame);
        out.tracking_ms = msSince(t0);
        out.t_ns = frame->t_ns;
        out.status = r.status;
        out.reason = r.reason;
        out.tracked = isTracked(r.status);
        out.T_w_c = r.T_w_c;
        keyframes_ += r.new_keyframe;
        out.keyframes = keyframes_;
      }
      ++processed_;
      tracked_ += out.tracked;
      if (listener_) listener_(out);
    }
  } catch (...) {
    // The System (or the listener) failed: stop taking frames; stop() rethrows.
    failure_ = std::current_exception();
    queue_.close();
  }
}

void LiveSession::save(const std::string& dir, const Json& stats_extra) {
  std::lock_guard<std::mutex> lock(feed_mutex_);
  writeRunOutputs(dir, system_, config_yaml_, stats_extra);
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
  stopped_ = true;
  queue_.close();
  thread_.join();
  if (failure_) std::rethrow_exception(failure_);
  system_.finish();
  const SessionCounts c = counts();
  kLog.info(str("received ", c.received, ", processed ", c.processed, ", dropped ", c.dropped, ", tracked ",
                c.tracked));
}

void LiveSession::writeOutputs(const std::string& dir, const Json& stats_extra, bool dense) {
  if (!stopped_) throw Error("LiveSession::writeOutputs before stop()");
  // The dense products first: the floor of their cloud gives the map frame of every output,
  // as in plslam run (without them the run outputs find the floor in the sparse map).
  const DenseOptions& dopt = system_.options().dense;
  if (!dense || !dopt.enabled) {
    writeRunOutputs(dir, system_, config_yaml_, stats_extra);
    return;
  }
  const DenseProducts products = buildDenseProducts(system_.map(), system_.camera(), dopt);
  writeDenseProducts(dir, products, {}, dopt);
  writeRunOutputs(dir, system_, config_yaml_, stats_extra, "", &products.frame);
}

}  // namespace plslam
