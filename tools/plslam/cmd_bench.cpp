// plslam bench: every TUM sequence of shared/data/tum and the chosen synthetic scenes, each
// run N times in threaded mode (docs/BENCHMARK.md: median with min and max), one Markdown
// table on stdout and in <out>/results.md, the same figures in <out>/results.json, each
// run's outputs in <out>/<sequence>/run<k>/ and a plot of the median run.
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <thread>

#include "progress_line.h"
#include "camera/camera_file.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/profile.h"
#include "eval/trajectory_plot.h"
#include "io/dataset.h"
#include "run_session.h"
#include "synth/dataset.h"
#include "synth/scene.h"
#include "system/run_outputs.h"
#include "system/system.h"

#ifndef PLSLAM_SOURCE_DIR
#define PLSLAM_SOURCE_DIR "."
#endif
#ifndef PLSLAM_BUILD_TYPE
#define PLSLAM_BUILD_TYPE ""
#endif

namespace plslam::cli {

namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A sequence to run: a TUM folder or a rendered synthetic scene.
struct SequenceSpec {
  std::string name;         ///< row name: the TUM folder's name or synthetic_<scene>
  std::string kind;         ///< "tum" or "synthetic"
  std::string dir;          ///< dataset folder (synthetic: filled once rendered)
  std::string camera_file;  ///< camera file
  synth::SceneKind scene = synth::SceneKind::kStatic;
  uint64_t seed = 1;        ///< synthetic: textures and noise (synth::SceneOptions::seed)
};

/// One run's figures.
struct RunFigures {
  int run = 0;  ///< 1-based
  std::string dir;
  int frames = 0, fed = 0, tracked = 0, keyframes = 0, skipped_frames = 0;
  double tracked_fraction = 0;
  double ate = kNaN, rpe_trans = kNaN, rpe_rot = kNaN;
  int ate_pairs = 0, rpe_pairs = 0;
  double tracking_median = 0, tracking_p95 = 0, tracking_max = 0, features_median = 0;
  std::array<double, kStageCount> stage_median{};  ///< per stage (core/profile.h), median over the frames
  double segmentation_median = kNaN;               ///< per segmented frame (on the segmenter's thread)
  double local_ba_median = kNaN;                   ///< per keyframe (on the mapping thread)
  double wall_s = 0;
  std::string eval_error;
  Trajectory estimate;  ///< kept for the plot of the median run
  AteResult ate_result;
};

struct SequenceResult {
  SequenceSpec spec;
  int frames = 0;  ///< associated frames in the folder
  std::vector<RunFigures> runs;
  int median_run = -1;  ///< index into runs of the run whose ATE is the median (plotted)
  std::string plot;
  double wall_s = 0, render_s = 0;
  double peak_rss_mb = 0;  ///< process peak so far, after this sequence
  std::string error;       ///< the sequence could not be completed
};

/// Median (summarize()'s convention), min and max over the finite values.
struct Spread {
  double median = kNaN, min = kNaN, max = kNaN;
  int count = 0;
};
Spread spread(const std::vector<double>& values) {
  std::vector<double> v;
  for (double x : values)
    if (std::isfinite(x)) v.push_back(x);
  Spread s;
  s.count = static_cast<int>(v.size());
  if (v.empty()) return s;
  s.median = summarize(v).median;
  s.min = *std::min_element(v.begin(), v.end());
  s.max = *std::max_element(v.begin(), v.end());
  return s;
}

template <typename F>
std::vector<double> collect(const std::vector<RunFigures>& runs, F f) {
  std::vector<double> v;
  for (const RunFigures& r : runs) v.push_back(f(r));
  return v;
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // kilobytes on Linux
}

std::string format(const char* fmt, double x) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, x);
  return buf;
}

/// "median (min-max)", the bare value when all runs agree, "n/a" without values; the
/// number of runs that gave a value when some did not.
std::string cell(const Spread& s, const char* fmt, int runs, double scale = 1.0) {
  if (s.count == 0) return "n/a";
  std::string text = format(fmt, s.median * scale);
  const std::string lo = format(fmt, s.min * scale), hi = format(fmt, s.max * scale);
  if (lo != hi) text += " (" + lo + "-" + hi + ")";
  if (s.count < runs) text += " [" + std::to_string(s.count) + "/" + std::to_string(runs) + " runs]";
  return text;
}

Json spreadJson(const Spread& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}, {"runs", s.count}};
}

// Empty text as null.
Json textOrNull(const std::string& text) { return text.empty() ? Json(nullptr) : Json(text); }

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

/// "1-7", "1,3,5" or a mix: seeds of at least 1, in the order given, each once.
std::vector<uint64_t> parseSeeds(const std::string& text) {
  auto fail = [&text]() -> std::vector<uint64_t> {
    throw ConfigError("--synthetic-seeds '" + text + "': give seeds of at least 1 as a list or ranges, e.g. 1-7 or 1,3,5");
  };
  auto number = [&](const std::string& t) -> uint64_t {
    if (t.empty() || t.find_first_not_of("0123456789") != std::string::npos || t.size() > 9) fail();
    const uint64_t v = std::stoull(t);
    if (v < 1) fail();
    return v;
  };
  std::vector<uint64_t> seeds;
  for (const std::string& item : splitList(text)) {
    const size_t dash = item.find('-');
    const uint64_t lo = number(item.substr(0, dash)), hi = dash == std::string::npos ? lo : number(item.substr(dash + 1));
    if (hi < lo || hi - lo >= 1000) fail();
    for (uint64_t v = lo; v <= hi; ++v)
      if (std::find(seeds.begin(), seeds.end(), v) == seeds.end()) seeds.push_back(v);
  }
  if (seeds.empty()) fail();
  return seeds;
}

/// The camera file of a TUM folder from its name (fr1/freiburg1...); empty when unknown.
std::string tumCameraFor(const std::string& name, const std::string& calib_dir) {
  std::string lower = name;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* n : {"1", "2", "3"})
    if (lower.find(std::string("fr") + n) != std::string::npos ||
        lower.find(std::string("freiburg") + n) != std::string::npos)
      return calib_dir + "/tum_freiburg" + n + ".xml";
  return "";
}

/// Renders the scene into `dir` unless an identical one (same scene.txt) is complete there.
/// Returns the seconds spent rendering (0 when reused).
double prepareSynthetic(const synth::Scene& scene, const std::string& dir, const std::string& name) {
  const fs::path root(dir);
  if (fs::exists(root / "rgb.txt") && fs::exists(root / "scene.txt")) {
    try {
      if (readTextFile((root / "scene.txt").string()) == scene.describe()) return 0;
    } catch (const Error&) {
      // unreadable: render again
    }
  }
  // A different scene (or an interrupted render): drop the old images so no stale frame stays
  // beside the new lists; the run folders are kept.
  std::error_code ec;
  fs::remove(root / "rgb.txt", ec);
  for (const char* sub : {"rgb", "depth", "masks"}) fs::remove_all(root / sub, ec);
  synth::DatasetOptions options;
  options.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const auto t0 = std::chrono::steady_clock::now();
  ProgressLine line("bench");
  options.progress = [&](int done, int total) {
    if (done % 10 != 0 && done != total) return;
    line.update("rendering %s: frame %d/%d", name.c_str(), done, total);
  };
  synth::writeDataset(scene, dir, options);
  line.done();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct BenchSettings {
  std::string out;
  int runs = 3;
  SystemOptions options;
  std::string config_yaml;
  bool masks = false;      ///< instance masks: the YOLO model on TUM rows, replayed masks on synthetic ones
  Pace pace = Pace::kRecorded;  ///< threaded runs: frames at their recorded times or as fast as possible
  std::string model;       ///< the YOLOv8-seg model for TUM rows with `masks`
};

/// The run options of one row: the bench's, with the row's segmenter when masks are asked for.
SystemOptions rowOptions(const BenchSettings& settings, const SequenceSpec& spec, const TumDataset& dataset) {
  SystemOptions o = settings.options;
  if (!o.dynamic.enabled) return o;
  if (!settings.masks) {  // the configuration's segmenter (segmenter.backend), on every row
    if (o.segmenter.kind == SegmenterKind::kReplay) o.segmenter.replay_labels = replayLabels(dataset);
    return o;
  }
  if (spec.kind == "synthetic") {
    o.segmenter.kind = SegmenterKind::kReplay;
    o.segmenter.replay_labels = replayLabels(dataset);
  } else {
    o.segmenter.kind = SegmenterKind::kYolo;
    o.segmenter.yolo.model_path = settings.model;
  }
  return o;
}

/// What the "dynamic" column says for a row.
std::string dynamicLabel(const BenchSettings& settings, const SequenceSpec& spec) {
  if (!settings.options.dynamic.enabled) return "no";
  if (!settings.masks) {
    const SegmenterKind kind = settings.options.segmenter.kind;
    return kind == SegmenterKind::kNone ? "geometry" : kind == SegmenterKind::kReplay ? "replayed masks" : "YOLO masks";
  }
  return spec.kind == "synthetic" ? "replayed masks" : "YOLO masks";
}

/// Feeds the dataset once through a started System, with a progress line; Ctrl-C ends the feed.
FeedResult feedRun(System* slam, TumDataset* dataset, const BenchSettings& settings, const SequenceSpec& spec, int k) {
  SigintGuard sigint;
  ProgressLine line("bench");
  const FeedResult fed = feedFrames(slam, dataset, [&](const FeedProgress& p) {
    line.update("%s run %d/%d frame %zu/%zu  tracked %d  keyframes %zu  %.1f frames/s", spec.name.c_str(), k,
                settings.runs, p.done, p.total, p.tracked, p.keyframes, p.done / std::max(p.seconds, 1e-9));
  }, 500, settings.options.sequential ? Pace::kAsFastAsPossible : settings.pace);
  line.done();
  return fed;
}

/// The figures of a finished run: counts, timing medians, and ATE/RPE when evaluated.
void fillRunFigures(const RunStats& st, const TumDataset& dataset, const RunEvaluation& ev, RunFigures* r) {
  r->fed = st.frames;
  r->tracked = st.tracked;
  r->keyframes = st.keyframes;
  r->skipped_frames = dataset.skippedTotal();
  // Frames with a pose / frames given (a frame that failed to load has no pose).
  r->tracked_fraction = r->frames ? static_cast<double>(r->estimate.size()) / r->frames : 0.0;
  const Summary tms = summarize(st.tracking_ms);
  r->tracking_median = tms.median;
  r->tracking_p95 = tms.p95;
  r->tracking_max = tms.max;
  r->features_median = summarize(st.features_ms).median;
  for (int i = 0; i < kStageCount; ++i) r->stage_median[i] = summarize(st.stage_ms[i]).median;
  if (!st.segmentation_ms.empty()) r->segmentation_median = summarize(st.segmentation_ms).median;
  if (!st.ba_ms.empty()) r->local_ba_median = summarize(st.ba_ms).median;
  if (ev.ok) {
    r->ate = ev.result.ate.stats.rmse;
    r->ate_pairs = ev.result.ate.stats.count;
    r->ate_result = ev.result.ate;
    r->rpe_pairs = ev.result.rpe.pairs;
    if (ev.result.rpe.pairs > 0) {
      r->rpe_trans = ev.result.rpe.trans.rmse;
      r->rpe_rot = ev.result.rpe.rot_deg.rmse;
    }
  } else {
    r->eval_error = ev.attempted ? ev.error
                                 : (dataset.hasGroundtruth() ? "fewer than 3 tracked frames" : "no ground truth");
  }
}

/// Plots the run whose ATE is the median one (the lower middle for an even count).
void plotMedianRun(const BenchSettings& settings, const TumDataset& dataset, const std::string& seq_out,
                   SequenceResult* result) {
  const SequenceSpec& spec = result->spec;
  std::vector<int> evaluated;
  for (size_t i = 0; i < result->runs.size(); ++i)
    if (std::isfinite(result->runs[i].ate)) evaluated.push_back(static_cast<int>(i));
  if (evaluated.empty()) return;
  std::sort(evaluated.begin(), evaluated.end(),
            [&](int a, int b) { return result->runs[a].ate < result->runs[b].ate; });
  result->median_run = evaluated[(evaluated.size() - 1) / 2];
  const RunFigures& m = result->runs[result->median_run];
  PlotOptions plot;
  plot.title = spec.name + ", run " + std::to_string(m.run) + " of " + std::to_string(result->runs.size()) +
               " (median ATE), " + (settings.options.sequential ? "sequential" : "threaded") +
               (settings.options.use_lines ? ", points+lines" : ", points only");
  result->plot = seq_out + "/trajectory.png";
  plotTrajectories(result->plot, dataset.groundtruth(), m.estimate, m.ate_result, plot);
}

/// Runs one sequence `runs` times; fills `result` (also on an error, with what is done).
void runSequence(const BenchSettings& settings, SequenceResult* result, bool* interrupted) {
  const SequenceSpec& spec = result->spec;
  const PinholeCamera camera = loadCameraFile(spec.camera_file);
  TumDataset dataset = TumDataset::open(spec.dir, camera);
  result->frames = static_cast<int>(dataset.size());
  const std::string seq_out = settings.out + "/" + spec.name;
  const SystemOptions options = rowOptions(settings, spec, dataset);

  for (int k = 1; k <= settings.runs && !*interrupted; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    dataset.rewind();
    System slam(camera, options);
    slam.start();
    const FeedResult fed = feedRun(&slam, &dataset, settings, spec, k);
    if (fed.interrupted) {
      *interrupted = true;
      std::fprintf(stderr, "[bench] interrupted: finishing this run, writing what there is, skipping the rest\n");
    }
    slam.finish();

    RunFigures r;
    r.run = k;
    r.dir = seq_out + "/run" + std::to_string(k);
    r.estimate = slam.trajectory();
    const RunEvaluation ev = evaluateRun(dataset, r.estimate);
    writeRunOutputs(r.dir, slam, settings.config_yaml, runStatsExtra(dataset, ev));
    r.frames = result->frames;
    fillRunFigures(slam.stats(), dataset, ev, &r);
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "[bench] %s run %d/%d: %s, tracked %.1f%%, %d keyframes, tracking %.1f ms median (%.1f s)\n",
                 spec.name.c_str(), k, settings.runs,
                 ev.ok ? format("ATE %.4f m", r.ate).c_str() : ("no ATE (" + r.eval_error + ")").c_str(),
                 100.0 * r.tracked_fraction, r.keyframes, r.tracking_median, r.wall_s);
    result->runs.push_back(std::move(r));
  }
  plotMedianRun(settings, dataset, seq_out, result);
}

std::string markdownTable(const std::vector<SequenceResult>& results, const BenchSettings& settings) {
  const int runs = settings.runs;
  const bool lines = settings.options.use_lines, loop = settings.options.use_loop;
  std::ostringstream os;
  os << "| sequence | frames | ATE RMSE m median (min-max) | RPE trans m/s | RPE rot deg/s | tracked | keyframes "
        "| tracking ms median / p95 | lines | dynamic | loop |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SequenceResult& s : results) {
    const auto& r = s.runs;
    const std::string dynamic = dynamicLabel(settings, s.spec);
    os << "| " << s.spec.name << " | " << s.frames << " | ";
    if (r.empty()) {
      os << "failed: " << s.error << " | | | | | | " << (lines ? "yes" : "no") << " | " << dynamic << " | " << (loop ? "yes" : "no") << " |\n";
      continue;
    }
    os << cell(spread(collect(r, [](const RunFigures& x) { return x.ate; })), "%.4f", runs) << " | "
       << cell(spread(collect(r, [](const RunFigures& x) { return x.rpe_trans; })), "%.4f", runs) << " | "
       << cell(spread(collect(r, [](const RunFigures& x) { return x.rpe_rot; })), "%.3f", runs) << " | "
       << cell(spread(collect(r, [](const RunFigures& x) { return x.tracked_fraction; })), "%.1f%%", runs, 100.0)
       << " | " << cell(spread(collect(r, [](const RunFigures& x) { return double(x.keyframes); })), "%.0f", runs)
       << " | " << format("%.1f", spread(collect(r, [](const RunFigures& x) { return x.tracking_median; })).median)
       << " / " << format("%.1f", spread(collect(r, [](const RunFigures& x) { return x.tracking_p95; })).median)
       << " | " << (lines ? "yes" : "no") << " | " << dynamic << " | " << (loop ? "yes" : "no") << " |\n";
  }
  return os.str();
}

/// Where the time goes (the role of PLY-SLAM's Table 8): per row, medians over the runs of
/// each run's per-frame median, per stage; the stages on the two extraction threads overlap.
std::string profileTable(const std::vector<SequenceResult>& results) {
  std::ostringstream os;
  os << "| sequence | tracking | tracking max | features + dynamic |";
  for (int i = 0; i < kStageCount; ++i) os << " " << stageName(static_cast<Stage>(i)) << " |";
  os << " segmentation (own thread) | local BA per keyframe (own thread) |\n|---|---|---|---|";
  for (int i = 0; i < kStageCount; ++i) os << "---|";
  os << "---|---|\n";
  auto median = [](const std::vector<RunFigures>& r, auto f) {
    const Spread s = spread(collect(r, f));
    return s.count ? format("%.1f", s.median) : std::string("-");
  };
  for (const SequenceResult& s : results) {
    if (s.runs.empty()) continue;
    const auto& r = s.runs;
    os << "| " << s.spec.name << " | " << median(r, [](const RunFigures& x) { return x.tracking_median; }) << " | "
       << median(r, [](const RunFigures& x) { return x.tracking_max; }) << " | "
       << median(r, [](const RunFigures& x) { return x.features_median; }) << " |";
    for (int i = 0; i < kStageCount; ++i) os << " " << median(r, [i](const RunFigures& x) { return x.stage_median[i]; }) << " |";
    os << " " << median(r, [](const RunFigures& x) { return x.segmentation_median; }) << " | "
       << median(r, [](const RunFigures& x) { return x.local_ba_median; }) << " |\n";
  }
  return os.str();
}

Json runJson(const RunFigures& x) {
  Json stages = Json::object();
  for (int st = 0; st < kStageCount; ++st) stages[stageName(static_cast<Stage>(st))] = x.stage_median[st];
  return {{"run", x.run},
          {"dir", x.dir},
          {"ate_rmse", x.ate},
          {"ate_pairs", x.ate_pairs},
          {"rpe_trans_rmse", x.rpe_trans},
          {"rpe_rot_rmse_deg", x.rpe_rot},
          {"rpe_pairs", x.rpe_pairs},
          {"frames_fed", x.fed},
          {"tracked", x.tracked},
          {"poses", x.estimate.size()},
          {"tracked_fraction", x.tracked_fraction},
          {"keyframes", x.keyframes},
          {"skipped_frames", x.skipped_frames},
          {"tracking_ms", {{"median", x.tracking_median}, {"p95", x.tracking_p95}, {"max", x.tracking_max}}},
          {"features_ms_median", x.features_median},
          {"stages_ms_median", stages},
          {"segmentation_ms_median", x.segmentation_median},
          {"local_ba_ms_median", x.local_ba_median},
          {"wall_s", x.wall_s},
          {"eval_error", textOrNull(x.eval_error)}};
}

Json sequenceJson(const SequenceResult& s, const BenchSettings& settings) {
  const auto& r = s.runs;
  const auto figure = [&](double (*of)(const RunFigures&)) { return spreadJson(spread(collect(r, of))); };
  Json runs = Json::array();
  for (const RunFigures& x : r) runs.push_back(runJson(x));
  return {{"sequence", s.spec.name},
          {"kind", s.spec.kind},
          {"seed", s.spec.kind == "synthetic" ? Json(s.spec.seed) : Json(nullptr)},
          {"dynamic", dynamicLabel(settings, s.spec)},
          {"dataset", s.spec.dir},
          {"camera", s.spec.camera_file},
          {"frames", s.frames},
          {"ate_rmse", figure([](const RunFigures& x) { return x.ate; })},
          {"rpe_trans_rmse", figure([](const RunFigures& x) { return x.rpe_trans; })},
          {"rpe_rot_rmse_deg", figure([](const RunFigures& x) { return x.rpe_rot; })},
          {"tracked_fraction", figure([](const RunFigures& x) { return x.tracked_fraction; })},
          {"keyframes", figure([](const RunFigures& x) { return double(x.keyframes); })},
          {"tracking_ms_median", figure([](const RunFigures& x) { return x.tracking_median; })},
          {"tracking_ms_p95", figure([](const RunFigures& x) { return x.tracking_p95; })},
          {"wall_s", s.wall_s},
          {"render_s", s.render_s},
          {"peak_rss_mb_so_far", s.peak_rss_mb},
          {"median_run", s.median_run >= 0 ? Json(r[s.median_run].run) : Json(nullptr)},
          {"plot", textOrNull(s.plot)},
          {"error", textOrNull(s.error)},
          {"runs", runs}};
}

std::string resultsJson(const std::vector<SequenceResult>& results, const std::vector<std::string>& notes,
                        const BenchSettings& settings, const std::string& shared, double peak_mb, double wall_s,
                        bool interrupted) {
  const SystemOptions& o = settings.options;
  Json sequences = Json::array();
  for (const SequenceResult& s : results) sequences.push_back(sequenceJson(s, settings));
  const Json j = {{"build_type", PLSLAM_BUILD_TYPE},
                  {"mode", o.sequential ? "sequential" : "threaded"},
                  {"pace", o.sequential ? "none" : settings.pace == Pace::kRecorded ? "recorded" : "fast"},
                  {"runs_per_sequence", settings.runs},
                  {"shared_dir", shared},
                  {"modules", {{"lines", o.use_lines}, {"dynamic", o.dynamic.enabled}, {"loop_closure", o.use_loop}}},
                  {"peak_rss_mb", peak_mb},
                  {"wall_s", wall_s},
                  {"interrupted", interrupted},
                  {"notes", notes},
                  {"sequences", sequences}};
  return jsonText(j);
}

/// Says `text` on stderr now and keeps it for the notes under the table.
void addNote(std::vector<std::string>* notes, const std::string& text) {
  std::fprintf(stderr, "[bench] %s\n", text.c_str());
  notes->push_back(text);
}

/// The bench's run options from its arguments.
BenchSettings benchSettings(const Args& args) {
  BenchSettings settings;
  settings.out = args.str("out");
  settings.runs = args.integer("runs", 1, 1000);
  // The switches bench shares with run go through run's one mapping (session/run_config.h),
  // so a configuration file's keys (the segmenter's too) mean the same here.
  RunSwitches switches;
  switches.config = args.str("config");
  switches.sequential = args.has("sequential");
  switches.no_lines = args.has("no-lines");
  switches.no_dynamic = args.has("no-dynamic");
  switches.no_loop = args.has("no-loop");
  RunConfig config = makeRunConfig(switches, "plslam bench: effective configuration");
  settings.options = std::move(config.options);
  settings.masks = args.has("masks");
  const std::string pace = args.str("pace");
  if (pace != "recorded" && pace != "fast") throw ConfigError("plslam bench: --pace must be recorded or fast, got '" + pace + "'");
  settings.pace = pace == "fast" ? Pace::kAsFastAsPossible : Pace::kRecorded;
  const std::string& key_model = settings.options.segmenter.yolo.model_path;
  settings.model = args.has("model")      ? args.str("model")
                   : !key_model.empty() ? key_model
                                        : (fs::path(args.str("shared")) / "models" / "yolov8n-seg-320.onnx").string();
  if (settings.masks && !settings.options.dynamic.enabled) throw ConfigError("plslam bench: --masks and --no-dynamic exclude each other");
  settings.config_yaml = config.config_yaml;
  return settings;
}

/// The rows to run, in table order: TUM folders by name, then the synthetic scenes; what is
/// skipped is said in `notes`. Throws when nothing is left or --masks lacks its model.
std::vector<SequenceSpec> benchRows(const Args& args, const BenchSettings& settings, std::vector<std::string>* notes) {
  std::vector<synth::SceneKind> scenes;
  const std::string scene_list = args.str("scenes");
  if (scene_list != "none")
    for (const std::string& name : splitList(scene_list)) {
      const synth::SceneKind kind = synth::parseSceneKind(name);
      if (std::find(scenes.begin(), scenes.end(), kind) == scenes.end()) scenes.push_back(kind);
    }
  auto note = [notes](const std::string& text) { addNote(notes, text); };
  std::vector<SequenceSpec> specs;
  const std::string shared = args.str("shared");
  const fs::path tum_root = fs::path(shared) / "data" / "tum";
  std::error_code ec;
  if (!fs::is_directory(tum_root, ec)) {
    note("TUM sequences skipped: " + tum_root.string() +
         " not found (give --shared DIR or set PLSLAM_SHARED_DIR); the synthetic scenes still run");
  } else {
    std::vector<fs::path> folders;
    for (const auto& entry : fs::directory_iterator(tum_root, ec))
      if (entry.is_directory() && fs::exists(entry.path() / "rgb.txt")) folders.push_back(entry.path());
    std::sort(folders.begin(), folders.end());
    if (folders.empty()) note("no TUM sequence (folder with rgb.txt) under " + tum_root.string());
    for (const fs::path& folder : folders) {
      SequenceSpec s;
      s.name = folder.filename().string();
      s.kind = "tum";
      s.dir = folder.string();
      s.camera_file = tumCameraFor(s.name, args.str("calib-dir"));
      if (s.camera_file.empty()) {
        note(s.name + " skipped: no camera for it (the folder name must say fr1/fr2/fr3 or freiburg1/2/3)");
        continue;
      }
      specs.push_back(s);
    }
  }
  // One rendering of a scene is one draw of its textures and noise; with several seeds each
  // is a row of its own (synthetic_<scene>_seed<N>), and seedSummary sums them up.
  const bool seeded = args.has("synthetic-seeds");
  const std::vector<uint64_t> seeds = seeded ? parseSeeds(args.str("synthetic-seeds")) : std::vector<uint64_t>{1};
  for (const synth::SceneKind kind : scenes)
    for (const uint64_t seed : seeds) {
      SequenceSpec s;
      s.name = std::string("synthetic_") + synth::sceneKindName(kind) + (seeded ? "_seed" + std::to_string(seed) : "");
      s.kind = "synthetic";
      s.dir = settings.out + "/" + s.name;
      s.camera_file = s.dir + "/camera.xml";
      s.scene = kind;
      s.seed = seed;
      specs.push_back(s);
    }
  if (args.has("sequences")) {
    const std::vector<std::string> wanted = splitList(args.str("sequences"));
    std::vector<SequenceSpec> kept;
    for (const SequenceSpec& s : specs)
      if (std::find(wanted.begin(), wanted.end(), s.name) != wanted.end()) kept.push_back(s);
    for (const std::string& w : wanted)
      if (std::none_of(specs.begin(), specs.end(), [&](const SequenceSpec& s) { return s.name == w; })) {
        std::string available;
        for (const SequenceSpec& s : specs) available += (available.empty() ? "" : ", ") + s.name;
        note("--sequences: no sequence named '" + w + "' (available: " + (available.empty() ? "none" : available) +
             "; synthetic ones need --scenes)");
      }
    specs = kept;
  }
  if (specs.empty()) throw ConfigError("plslam bench: no sequence to run (see the lines above)");
  // A missing model is refused before hours of runs, not found out at the first TUM row.
  if (settings.masks && std::any_of(specs.begin(), specs.end(), [](const SequenceSpec& s) { return s.kind == "tum"; }) &&
      !fs::is_regular_file(settings.model, ec))
    throw IoError(settings.model + ": no such model file (--masks needs a YOLOv8-seg ONNX model for the TUM rows; give --model)");

  return specs;
}

/// Per synthetic scene run with several seeds: the median and the worst of the rows' ATE
/// (each row's own median over its runs), one line each.
std::string seedSummary(const std::vector<SequenceResult>& results) {
  std::string out;
  std::vector<synth::SceneKind> done;
  for (const SequenceResult& first : results) {
    if (first.spec.kind != "synthetic" || std::count(done.begin(), done.end(), first.spec.scene)) continue;
    done.push_back(first.spec.scene);
    std::vector<double> ate;
    std::vector<uint64_t> seed;  // per ATE
    for (const SequenceResult& r : results) {
      if (r.spec.kind != "synthetic" || r.spec.scene != first.spec.scene) continue;
      ate.push_back(spread(collect(r.runs, [](const RunFigures& x) { return x.ate; })).median);
      seed.push_back(r.spec.seed);
    }
    if (ate.size() < 2) continue;
    const Spread s = spread(ate);
    const auto worst = std::find(ate.begin(), ate.end(), s.max);  // NaN when no seed has an ATE: not found
    out += "- synthetic " + std::string(synth::sceneKindName(first.spec.scene)) + " over " + std::to_string(ate.size()) +
           " seeds: ATE median " + format("%.4f", s.median) + " m, worst " + format("%.4f", s.max) + " m" +
           (worst != ate.end() ? " (seed " + std::to_string(seed[worst - ate.begin()]) + ")" : "") +
           (s.count < static_cast<int>(ate.size()) ? ", some seeds without an ATE" : "") + "\n";
  }
  return out;
}

/// Prints the tables and writes results.md and results.json.
void writeBenchReport(const std::vector<SequenceResult>& results, const std::vector<std::string>& notes,
                      const BenchSettings& settings, const std::string& shared, double wall_s, bool interrupted) {
  const double peak_mb = peakRssMb();
  const std::string table_md = markdownTable(results, settings);
  const std::string profile_md =
      "\nWhere a frame's time goes, ms (medians over the runs of each run's per-frame median; ORB and the dynamic "
      "check on one thread overlap LSD, merge and LBD on the other):\n\n" +
      profileTable(results);
  std::ostringstream under;
  under << "\n"
        << (settings.options.sequential ? "Sequential"
            : settings.pace == Pace::kRecorded ? "Threaded mode, frames fed at their recorded times (as a camera delivers "
                                                 "them)"
                                               : "Threaded mode, frames fed as fast as they are tracked")
        << (settings.options.sequential ? " mode, " : ", ") << settings.runs
        << (settings.runs == 1 ? " run" : " runs") << " per sequence: median (min-max) over the runs; RPE over 1 s "
        << "windows; tracked = frames with a pose / frames given; tracking ms = medians over the runs of each run's "
           "median / 95th percentile. Build: "
        << (std::string(PLSLAM_BUILD_TYPE).empty() ? "unknown" : PLSLAM_BUILD_TYPE) << ".\n";
  under << "Peak resident memory (whole process): " << format("%.0f", peak_mb) << " MB. Wall time per sequence (all runs";
  under << "): ";
  for (size_t i = 0; i < results.size(); ++i)
    under << (i ? ", " : "") << results[i].spec.name << " " << format("%.1f", results[i].wall_s) << " s";
  under << "; total " << format("%.1f", wall_s) << " s.\n";
  under << seedSummary(results);
  for (const std::string& n : notes) under << "- " << n << "\n";
  if (interrupted) under << "- interrupted by Ctrl-C: the table holds what was done\n";

  std::cout << table_md << profile_md << under.str();
  std::cout.flush();
  writeFileAtomically(settings.out + "/results.md", "# plslam bench\n\n" + table_md + profile_md + under.str());
  writeFileAtomically(settings.out + "/results.json",
                      resultsJson(results, notes, settings, shared, peak_mb, wall_s, interrupted));
  std::fprintf(stderr, "[bench] wrote %s/results.md and results.json\n", settings.out.c_str());
}

/// The options of plslam bench.
void declareBenchOptions(Args& args, const std::string& default_shared) {
  args.option("shared", "the shared/ folder with data/tum/ ($PLSLAM_SHARED_DIR, else <source>/../shared)",
              default_shared)
      .option("calib-dir", "folder with tum_freiburg{1,2,3}.xml", std::string(PLSLAM_SOURCE_DIR) + "/calib")
      .option("out", "output folder: results.md, results.json, <sequence>/run<k>/, synthetic_<scene>/",
              "maps/bench")
      .option("runs", "runs per sequence (the table gives the median with min and max)", "3")
      .option("synthetic-frames", "frames of each synthetic scene [default: the scene's own, 300; loop 450]")
      .option("scenes", "synthetic scenes, comma-separated: static, dynamic, loop, crowded; or none", "static")
      .option("synthetic-seeds",
              "render each synthetic scene with each of these seeds (textures and noise), one row each, "
              "e.g. 1-7 or 1,3,5; the report adds each scene's median and worst ATE over them [default: 1]")
      .option("sequences", "only these rows, comma-separated (TUM folder names, synthetic_<scene>)")
      .option("config", "YAML run options (as plslam run --config)")
      .flag("no-lines", "points only: no line features")
      .flag("no-dynamic", "no rejection of moving objects (default: geometric checks, no segmenter)")
      .flag("masks", "instance masks too: TUM rows through the YOLOv8-seg model of --model, synthetic rows replayed from their masks/")
      .option("model", "YOLOv8-seg ONNX model for --masks [default: segmenter.model of --config, else "
                       "<shared>/models/yolov8n-seg-320.onnx]")
      .flag("no-loop", "no loop closure")
      .flag("sequential", "deterministic single-thread order instead of the threaded mode")
      .option("pace", "threaded runs: 'recorded' feeds each frame at its recorded time, as a camera delivers them (and as "
                      "ORB-SLAM2's TUM example does); 'fast' feeds the next frame as soon as the last is tracked",
              "recorded")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .epilog(
          "TUM folders (those with rgb.txt) take their camera from the name: fr1/freiburg1 -> tum_freiburg1.xml,\n"
          "fr2 -> tum_freiburg2.xml, fr3 -> tum_freiburg3.xml; other names are skipped with a warning.\n"
          "Synthetic scenes are rendered once into <out>/synthetic_<scene> and reused while scene.txt matches.\n"
          "Measure a Release build; the machine's load shows in the times.\n\n"
          "example: plslam bench --runs 3 --scenes static,dynamic --out maps/bench\n"
          "         plslam bench --runs 3 --scenes dynamic,crowded --masks --out maps/bench_masks\n"
          "         plslam bench --runs 1 --sequential --scenes crowded --synthetic-seeds 1-7 --out maps/seeds");
}

/// One row: the synthetic scene rendered (or reused) first, then its runs; an error is noted
/// and leaves the row with what is done.
SequenceResult benchRow(const SequenceSpec& spec, const BenchSettings& settings, int synthetic_frames,
                        bool* interrupted, bool* failed, std::vector<std::string>* notes) {
  SequenceResult result;
  result.spec = spec;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (spec.kind == "synthetic") {
      synth::SceneOptions scene_options;
      scene_options.frames = synthetic_frames > 0 ? synthetic_frames : synth::defaultFrameCount(spec.scene);
      scene_options.seed = spec.seed;
      result.render_s = prepareSynthetic(synth::makeScene(spec.scene, scene_options), spec.dir, spec.name);
    }
    const auto runs_t0 = std::chrono::steady_clock::now();
    runSequence(settings, &result, interrupted);
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - runs_t0).count();
  } catch (const Error& e) {
    result.error = e.what();
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    *failed = true;
    addNote(notes, spec.name + " failed: " + result.error);
  }
  result.peak_rss_mb = peakRssMb();
  return result;
}

int runBench(int argc, char** argv) {
  const char* env_shared = std::getenv("PLSLAM_SHARED_DIR");
  const std::string default_shared =
      env_shared && *env_shared ? env_shared
                                 : (fs::path(PLSLAM_SOURCE_DIR) / ".." / "shared").lexically_normal().string();
  Args args("bench",
            "Benchmark: every TUM sequence of <shared>/data/tum and synthetic scenes, N threaded runs each, "
            "one Markdown table (docs/BENCHMARK.md).");
  declareBenchOptions(args, default_shared);
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));
  const auto bench_t0 = std::chrono::steady_clock::now();

  const BenchSettings settings = benchSettings(args);
  const int synthetic_frames = args.has("synthetic-frames") ? args.integer("synthetic-frames", 2, 1000000) : 0;
  if (std::string(PLSLAM_BUILD_TYPE) != "Release")
    std::fprintf(stderr, "[bench] warning: this is a '%s' build, not Release: times are not representative\n",
                 PLSLAM_BUILD_TYPE);

  std::vector<std::string> notes;  // skips and warnings, printed under the table
  const std::vector<SequenceSpec> specs = benchRows(args, settings, &notes);
  const std::string shared = args.str("shared");
  std::error_code ec;
  fs::create_directories(settings.out, ec);
  if (!fs::is_directory(settings.out)) throw IoError(settings.out + ": cannot create the output folder");

  std::vector<SequenceResult> results;
  bool interrupted = false, failed = false;
  for (const SequenceSpec& spec : specs) {
    if (interrupted) break;
    results.push_back(benchRow(spec, settings, synthetic_frames, &interrupted, &failed, &notes));
  }

  writeBenchReport(results, notes, settings, shared,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - bench_t0).count(), interrupted);
  return interrupted ? 130 : failed ? 1 : 0;
}

}  // namespace

Command makeBenchCommand() {
  return {"bench", "run every TUM sequence and synthetic scene N times; one Markdown table of ATE, RPE, speed",
          runBench};
}

}  // namespace plslam::cli
