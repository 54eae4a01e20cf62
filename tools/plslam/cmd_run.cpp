// plslam run: SLAM over a recorded RGB-D folder (TUM layout), writing the trajectory,
// keyframes, sparse map, statistics and effective configuration.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "progress_line.h"
#include "camera/camera_file.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "frame_source_open.h"
#include "io/dataset.h"
#include "mapping_session.h"
#include "run_session.h"
#include "session/run_config.h"
#include "system/run_outputs.h"
#include "system/system.h"

namespace plslam::cli {

namespace {

// The command line of plslam run.
Args runArguments() {
  Args args("run", "Point-line RGB-D SLAM over a recorded folder (TUM RGB-D layout, ICL-NUIM, or plslam synth).");
  args.option("dataset", "folder with rgb.txt and depth.txt (or associations.txt), or a ROS bag (FILE.bag)", "", true)
      .option("calib", "camera file (ViSP XML, see calib/); with --map, default: the map's camera; a bag's default: its camera_info")
      .option("groundtruth", "TUM trajectory to evaluate against (default: the folder's groundtruth.txt; a bag has none)")
      .option("out", "output folder (created if needed)", "", true)
      .option("max-frames", "process only the first N frames (0 = all)", "0")
      .flag("sequential", "deterministic single-thread order (identical output across runs)")
      .flag("realtime", "feed each frame at its recorded time, as a camera would (the mapping threads get the time between frames)")
      .flag("no-dense", "do not write the dense products (cloud, OctoMaps, 2D grid), neither while running nor at the end")
      .flag("print-config", "print the effective configuration and exit")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .flag("quiet", "no progress line")
      .option("save-map", "where to write the map at the end (default: <out>/map.plmap)");
  addRunSwitches(&args);
  args.epilog(
          "outputs: trajectory.txt (TUM, every tracked frame, first camera's frame), trajectory_map.txt (the same in the\n"
          "map frame), keyframes.txt, map_frame.yaml, sparse_map.ply, stats.json, config.yaml,\n"
          "map.plmap (the map, for --map; written atomically, also after Ctrl-C)\n"
          "and the dense products (unless --no-dense; see plslam export): dense_cloud.pcd, dense_cloud_semantic.ply,\n"
          "octomap.bt, octomap_semantic.ot, octomap_labels.ot, grid.pgm + grid.yaml, dense_products.json; these are also updated while\n"
          "the run goes on, every dense.live_every_keyframes keyframes or dense.live_every_s seconds (see --print-config)\n"
          "Every world-frame output but trajectory.txt and keyframes.txt is in the map frame (z up, x forward,\n"
          "origin on the floor below the first camera, or below the base with --base; map_frame.yaml holds T_map_world).\n"
          "With --base (or calibration.camera_to_base), trajectory_base.txt holds the base's poses in the map frame.\n"
          "When the folder has groundtruth.txt, the ATE is printed and added to stats.json.\n"
          "Ctrl-C stops the run and still writes what it has.\n\n"
          "A bag is read in TUM's layout (/camera/rgb/image_color, /camera/depth/image in float metres,\n"
          "/camera/rgb/camera_info) or the RealSense driver's (/camera/color/image_raw,\n"
          "/camera/aligned_depth_to_color/image_raw in millimetres, /camera/color/camera_info).\n\n"
          "example: plslam run --dataset rgbd_dataset_freiburg1_xyz --calib calib/tum_freiburg1.xml --out maps/fr1_xyz");
  return args;
}

// The figures of a finished run, on stdout.
void printSummary(const RunStats& st, const FrameSource& dataset, const std::string& ate_line, const std::string& out) {
  const Summary tms = summarize(st.tracking_ms);
  std::printf("frames %d, tracked %d (%.1f%%), keyframes %d, lost %d, map %d points %d lines\n", st.frames, st.tracked,
              st.frames ? 100.0 * st.tracked / st.frames : 0.0, st.keyframes, st.lost_events, st.map_points, st.map_lines);
  std::printf("tracking %.1f ms/frame median, %.1f p95, %.1f max; line reconstruction rate: fitting %.3f, endpoints %.3f\n",
              tms.median, tms.p95, tms.max, st.line_rate_fitting, st.line_rate_endpoints);
  const std::string skipped = dataset.skippedText();
  if (!skipped.empty()) std::printf("skipped %d of %zu frames: %s\n", dataset.skippedTotal(), dataset.size(), skipped.c_str());
  if (!ate_line.empty()) std::printf("%s\n", ate_line.c_str());
  std::printf("outputs: %s\n", out.c_str());
}

// The folder or bag of --dataset with the camera its frames are read with (--calib, a
// bag's camera_info, or the saved map's camera), and the replay segmenter's labels.
OpenedSource openRunSource(const Args& args, RunConfig* config) {
  std::optional<PinholeCamera> calib;
  if (args.has("calib")) calib = loadCameraFile(args.str("calib"));
  else if (config->map && !isBagPath(args.str("dataset"))) calib = config->map->camera;
  DatasetOptions dopt;
  dopt.max_frames = args.integer("max-frames", 0, 100000000);
  dopt.groundtruth_file = args.str("groundtruth");
  // Instance masks are the replay segmenter's input and nothing else's: a folder whose
  // masks/ are in another format (binary walker masks, say) must still run without it.
  dopt.load_masks = config->options.segmenter.kind == SegmenterKind::kReplay;
  OpenedSource opened = openFrameSource(args.str("dataset"), calib ? &*calib : nullptr, dopt);
  const FrameSource& dataset = *opened.source;
  const PinholeCamera& camera = opened.camera;
  if (config->map && (camera.width != config->map->camera.width || camera.height != config->map->camera.height ||
                      camera.fx != config->map->camera.fx || camera.fy != config->map->camera.fy))
    std::fprintf(stderr, "[run] warning: the camera differs from the one the map was built with\n");
  SegmenterOptions& segmenter = config->options.segmenter;
  if (segmenter.kind == SegmenterKind::kReplay) {
    const auto* folder = dynamic_cast<const TumDataset*>(&dataset);
    if (!folder || (folder->instanceLabels().empty() && folder->listReport().masks_listed == 0))
      throw ConfigError("plslam run: the replay segmenter (--segmenter replay, segmenter.backend) needs a folder "
                        "with masks.txt (plslam synth writes one): " +
                        dataset.location());
    segmenter.replay_labels = replayLabels(*folder);
  }
  return opened;
}

int runRun(int argc, char** argv) {
  Args args = runArguments();
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));

  const bool bag = isBagPath(args.str("dataset"));
  RunConfig config;
  try {
    config = makeRunConfig(runSwitches(args), "plslam run: effective configuration");
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("plslam run: ") + e.what());
  }
  if (!bag && !args.has("calib") && !args.has("map")) throw ConfigError("plslam run: --calib is required (or --map)");
  SystemOptions& options = config.options;
  if (args.has("print-config")) {
    std::cout << config.config_yaml;
    return 0;
  }

  OpenedSource opened = openRunSource(args, &config);
  FrameSource& dataset = *opened.source;
  const PinholeCamera camera = opened.camera;
  const std::string out = args.str("out");
  // Refuse an unusable output folder before the run, not after it.
  {
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (!std::filesystem::is_directory(out))
      throw IoError(out + ": cannot create the output folder" + (ec ? " (" + ec.message() + ")" : std::string()));
  }

  // Ctrl-C stops the frames; from then on it must not end the process, which would leave a
  // half-written file (a live map update finishing, say). Made before the session, so that
  // it outlives the session's threads too.
  SigintGuard sigint;
  MappingSession session(camera, &config, out, !args.has("no-dense") && options.dense.enabled);
  System& slam = session.slam();
  session.start();
  const bool progress = !args.has("quiet");
  FeedResult fed;
  {
    ProgressLine line("run");
    fed = feedFrames(&slam, &dataset, [&](const FeedProgress& p) {
      if (!progress) return;
      line.update("frame %zu/%zu  tracked %d  keyframes %zu  %.1f frames/s", p.done, p.total, p.tracked, p.keyframes,
                  p.done / std::max(p.seconds, 1e-9));
    }, 500, args.has("realtime") ? Pace::kRecorded : Pace::kAsFastAsPossible);
    line.done();
  }
  if (fed.interrupted) std::fprintf(stderr, "[run] interrupted: finishing and writing what there is\n");
  session.stop();
  const std::string skipped = dataset.skippedText();
  // A run that tracked nothing has no result: say why and leave the output folder as it was.
  if (fed.tracked == 0) {
    if (fed.interrupted) {
      std::fprintf(stderr, "[run] interrupted before any frame was tracked: no outputs written to %s\n", out.c_str());
      return 130;
    }
    if (fed.fed == 0)
      throw DataError(str(dataset.location(), ": none of the ", dataset.size(), " frames could be loaded (", skipped,
                          "); see the messages above for each file"));
    throw DataError(str(dataset.location(), ": none of the ", fed.fed, " frames loaded could be tracked (last reason: ",
                        fed.last_failure, ")", skipped.empty() ? "" : "; skipped: " + skipped));
  }

  const RunEvaluation evaluation = evaluateRun(dataset, slam.trajectory());
  const std::string ate_line = evaluation.text();
  const bool dense_done = session.writeOutputs(runStatsExtra(dataset, evaluation), args.str("save-map"), progress);

  printSummary(slam.stats(), dataset, ate_line, out);
  if (!dense_done) return 130;
  return fed.interrupted ? 130 : 0;
}

}  // namespace

Command makeRunCommand() { return {"run", "SLAM over a recorded RGB-D folder (TUM layout)", runRun}; }

}  // namespace plslam::cli
