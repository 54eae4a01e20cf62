// plslam run: SLAM over a recorded RGB-D folder (TUM layout), writing the trajectory,
// keyframes, sparse map, statistics and effective configuration.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "camera/camera_file.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "eval/trajectory_eval.h"
#include "io/dataset.h"
#include "system/run_outputs.h"
#include "system/system.h"

namespace plslam::cli {

namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void onSigint(int) { g_interrupted = true; }

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open configuration file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int runRun(int argc, char** argv) {
  Args args("run", "Point-line RGB-D SLAM over a recorded folder (TUM RGB-D layout, ICL-NUIM, or plslam synth).");
  args.option("dataset", "folder with rgb.txt and depth.txt (or associations.txt)", "", true)
      .option("calib", "camera file (ViSP XML, see calib/)", "", true)
      .option("out", "output folder (created if needed)", "", true)
      .option("config", "YAML run options (plslam run --print-config shows every key)")
      .option("max-frames", "process only the first N frames (0 = all)", "0")
      .flag("sequential", "deterministic single-thread order (identical output across runs)")
      .flag("no-lines", "points only: no line features")
      .flag("print-config", "print the effective configuration and exit")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .flag("quiet", "no progress line")
      .epilog(
          "outputs: trajectory.txt (TUM, every tracked frame), keyframes.txt, sparse_map.ply, stats.json, config.yaml\n"
          "When the folder has groundtruth.txt, the ATE is printed and added to stats.json.\n"
          "Ctrl-C stops the run and still writes what it has.\n\n"
          "example: plslam run --dataset rgbd_dataset_freiburg1_xyz --calib calib/tum_freiburg1.xml --out maps/fr1_xyz");
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));

  SystemOptions options;
  OptionTable table;
  bindOptions(&table, &options);
  if (args.has("config")) {
    const std::string path = args.str("config");
    table.apply(parseYamlSubset(readText(path), path), path);
  }
  if (args.has("sequential")) options.sequential = true;
  if (args.has("no-lines")) options.use_lines = false;
  if (args.has("print-config")) {
    std::cout << table.toYaml("plslam run: effective configuration");
    return 0;
  }

  const PinholeCamera camera = loadCameraFile(args.str("calib"));
  DatasetOptions dopt;
  dopt.max_frames = args.integer("max-frames", 0, 100000000);
  TumDataset dataset = TumDataset::open(args.str("dataset"), camera, dopt);
  const std::string out = args.str("out");

  System slam(camera, options);
  slam.start();
  g_interrupted = false;
  auto previous = std::signal(SIGINT, onSigint);
  const bool progress = !args.has("quiet");
  const auto t0 = std::chrono::steady_clock::now();
  auto last_print = t0;
  RgbdFrame frame;
  size_t done = 0;
  int tracked = 0;
  while (!g_interrupted && dataset.next(&frame)) {
    const TrackingResult r = slam.feed(frame);
    ++done;
    tracked += isTracked(r.status);
    const auto now = std::chrono::steady_clock::now();
    if (progress && (now - last_print > std::chrono::milliseconds(500) || done == dataset.size())) {
      last_print = now;
      const double s = std::chrono::duration<double>(now - t0).count();
      std::fprintf(stderr, "\r[run] frame %zu/%zu  tracked %d  keyframes %zu  %.1f frames/s  ", done, dataset.size(),
                   tracked, slam.map().keyframes().size(), done / std::max(s, 1e-9));
      std::fflush(stderr);
    }
  }
  if (progress) std::fprintf(stderr, "\n");
  std::signal(SIGINT, previous);
  if (g_interrupted) std::fprintf(stderr, "[run] interrupted: finishing and writing what there is\n");
  slam.finish();

  std::ostringstream extra;
  extra << "\"dataset\": \"" << dataset.dir() << "\", \"skipped_frames\": " << dataset.skippedTotal();
  std::string ate_line;
  const Trajectory est = slam.trajectory();
  if (dataset.hasGroundtruth() && est.size() >= 3) {
    try {
      const EvalResult ev = evaluate(dataset.groundtruth(), est);
      extra.precision(6);
      extra << ", \"ate_rmse_m\": " << ev.ate.stats.rmse << ", \"rpe_trans_rmse_m\": " << ev.rpe.trans.rmse
            << ", \"rpe_rot_rmse_deg\": " << ev.rpe.rot_deg.rmse;
      char buf[160];
      std::snprintf(buf, sizeof(buf), "ATE RMSE %.4f m over %d poses; RPE %.4f m/s, %.3f deg/s", ev.ate.stats.rmse,
                    ev.ate.stats.count, ev.rpe.trans.rmse, ev.rpe.rot_deg.rmse);
      ate_line = buf;
    } catch (const Error& e) {
      ate_line = std::string("ATE not computed: ") + e.what();
    }
  }
  writeRunOutputs(out, slam, table.toYaml("plslam run: effective configuration"), extra.str());

  const RunStats st = slam.stats();
  const Summary tms = summarize(st.tracking_ms);
  std::printf("frames %d, tracked %d (%.1f%%), keyframes %d, lost %d, map %d points %d lines\n", st.frames, st.tracked,
              st.frames ? 100.0 * st.tracked / st.frames : 0.0, st.keyframes, st.lost_events, st.map_points, st.map_lines);
  std::printf("tracking %.1f ms/frame median, %.1f p95; line reconstruction rate: fitting %.3f, endpoints %.3f\n",
              tms.median, tms.p95, st.line_rate_fitting, st.line_rate_endpoints);
  if (!ate_line.empty()) std::printf("%s\n", ate_line.c_str());
  std::printf("outputs: %s\n", out.c_str());
  return g_interrupted ? 130 : 0;
}

}  // namespace

Command makeRunCommand() { return {"run", "SLAM over a recorded RGB-D folder (TUM layout)", runRun}; }

}  // namespace plslam::cli
