#include "run_session.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "frontend/tracker.h"

namespace plslam::cli {

void addRunSwitches(Args* args) {
  args->option("config", "YAML run options (plslam run --print-config shows every key)")
      .flag("no-lines", "points only: no line features")
      .option("segmenter", "instance masks: none, replay (the folder's masks/, as plslam synth writes), yolo (the model "
                           "of segmenter.model) or a YOLOv8-seg .onnx file [default: the key segmenter.backend, none]")
      .option("classes", "class names file, one a line, in the model's order [default: segmenter.classes, the COCO names]")
      .option("dynamic-classes", "comma-separated class names that may move [default: segmenter.dynamic_classes: person, "
                                 "animals, vehicles]")
      .flag("allow-missing-model", "if the model cannot be used, warn and go on with the geometric checks only "
                                   "(segmenter.allow_missing_model)")
      .flag("no-dynamic", "no rejection of moving objects at all")
      .flag("no-loop", "no loop closure")
      .option("map", "start from a saved map (a run's map.plmap); its configuration is the base of this run's")
      .flag("localize", "with --map: track in the map without changing it (no keyframes, no mapping); poses in its world frame")
      .option("base", "camera-to-base file of plslam calib base (over the key calibration.camera_to_base): the map "
                      "frame's origin is then below the robot base, x its forward; writes trajectory_base.txt");
}

RunSwitches runSwitches(const Args& args) {
  RunSwitches switches;
  switches.config = args.str("config");
  switches.map = args.str("map");
  switches.localize = args.has("localize");
  switches.sequential = args.has("sequential");
  switches.no_lines = args.has("no-lines");
  switches.no_dynamic = args.has("no-dynamic");
  switches.no_loop = args.has("no-loop");
  switches.segmenter = args.str("segmenter");
  switches.classes = args.str("classes");
  switches.dynamic_classes = args.str("dynamic-classes");
  switches.allow_missing_model = args.has("allow-missing-model");
  switches.base = args.str("base");
  return switches;
}

namespace {
std::atomic<bool> g_interrupted{false};
extern "C" void onSigint(int) { g_interrupted = true; }
}  // namespace

std::vector<InstanceClass> replayLabels(const TumDataset& dataset) {
  std::vector<InstanceClass> out;
  for (const InstanceLabel& l : dataset.instanceLabels()) out.push_back({l.instance_id, l.class_id, l.class_name});
  return out;
}

SigintGuard::SigintGuard() {
  g_interrupted = false;
  previous_ = std::signal(SIGINT, onSigint);
}
SigintGuard::~SigintGuard() { std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_); }
bool SigintGuard::interrupted() { return g_interrupted; }

FeedResult feedFrames(System* slam, FrameSource* source, const std::function<void(const FeedProgress&)>& progress,
                      int period_ms, Pace pace) {
  FeedResult result;
  const auto t0 = std::chrono::steady_clock::now();
  auto last_report = t0;
  size_t reported = 0;
  bool any_report = false;
  auto report = [&](std::chrono::steady_clock::time_point now) {
    last_report = now;
    if (!progress || (any_report && reported == result.fed)) return;
    reported = result.fed;
    any_report = true;
    FeedProgress p;
    p.done = result.fed;
    p.total = source->size();
    p.tracked = result.tracked;
    p.keyframes = slam->keyframeCount();
    p.seconds = std::chrono::duration<double>(now - t0).count();
    progress(p);
  };
  RgbdFrame frame;
  std::optional<TimeNs> first_stamp;
  while (!g_interrupted && source->next(&frame)) {
    if (pace == Pace::kRecorded) {
      if (!first_stamp) first_stamp = frame.t_ns;
      std::this_thread::sleep_until(t0 + std::chrono::nanoseconds(frame.t_ns - *first_stamp));
    }
    const TrackingResult r = slam->feed(frame);
    ++result.fed;
    result.tracked += isTracked(r.status);
    if (!isTracked(r.status) && !r.reason.empty()) result.last_failure = r.reason;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_report > std::chrono::milliseconds(period_ms)) report(now);
  }
  const auto end = std::chrono::steady_clock::now();
  report(end);
  result.seconds = std::chrono::duration<double>(end - t0).count();
  result.interrupted = g_interrupted;
  return result;
}

Json RunEvaluation::jsonMembers() const {
  if (!ok) return Json::object();
  return {{"ate_rmse_m", result.ate.stats.rmse},
          {"rpe_trans_rmse_m", result.rpe.trans.rmse},
          {"rpe_rot_rmse_deg", result.rpe.rot_deg.rmse}};
}

std::string RunEvaluation::text() const {
  if (!attempted) return "";
  if (!ok) return "ATE not computed: " + error;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "ATE RMSE %.4f m over %d poses; RPE %.4f m/s, %.3f deg/s", result.ate.stats.rmse,
                result.ate.stats.count, result.rpe.trans.rmse, result.rpe.rot_deg.rmse);
  return buf;
}

RunEvaluation evaluateRun(const FrameSource& source, const Trajectory& estimate) {
  RunEvaluation ev;
  if (!source.hasGroundtruth() || estimate.size() < 3) return ev;
  ev.attempted = true;
  try {
    ev.result = evaluate(source.groundtruth(), estimate);
    ev.ok = true;
  } catch (const Error& e) {
    ev.error = e.what();
  }
  return ev;
}

Json runStatsExtra(const FrameSource& source, const RunEvaluation& evaluation) {
  Json extra = {{"dataset", source.location()}, {"skipped_frames", source.skippedTotal()}};
  extra.update(evaluation.jsonMembers());
  return extra;
}

}  // namespace plslam::cli
