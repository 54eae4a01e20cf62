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
#include "dense_cli.h"
#include "io/dataset.h"
#include "mapfile/map_file.h"
#include "run_session.h"
#include "system/run_outputs.h"
#include "system/system.h"

namespace plslam::cli {

namespace {

int runRun(int argc, char** argv) {
  Args args("run", "Point-line RGB-D SLAM over a recorded folder (TUM RGB-D layout, ICL-NUIM, or plslam synth).");
  args.option("dataset", "folder with rgb.txt and depth.txt (or associations.txt)", "", true)
      .option("calib", "camera file (ViSP XML, see calib/); with --map, default: the map's camera")
      .option("out", "output folder (created if needed)", "", true)
      .option("config", "YAML run options (plslam run --print-config shows every key)")
      .option("max-frames", "process only the first N frames (0 = all)", "0")
      .flag("sequential", "deterministic single-thread order (identical output across runs)")
      .flag("realtime", "feed each frame at its recorded time, as a camera would (the mapping threads get the time between frames)")
      .flag("no-lines", "points only: no line features")
      .option("segmenter", "instance masks: none, replay (the folder's masks/, as plslam synth writes), or a YOLOv8-seg .onnx file",
              "none")
      .option("classes", "class names file, one a line, in the model's order (default: the COCO names)")
      .option("dynamic-classes", "comma-separated class names that may move (default: person, animals, vehicles)")
      .flag("allow-missing-model", "if the model cannot be used, warn and go on with the geometric checks only")
      .flag("no-dynamic", "no rejection of moving objects at all")
      .flag("no-loop", "no loop closure")
      .flag("no-dense", "do not write the dense products (cloud, OctoMaps, 2D grid) at the end")
      .flag("print-config", "print the effective configuration and exit")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .flag("quiet", "no progress line")
      .option("map", "start from a saved map (a run's map.plmap); its configuration is the base of this run's")
      .flag("localize", "with --map: track in the map without changing it (no keyframes, no mapping); poses in its world frame")
      .option("save-map", "where to write the map at the end (default: <out>/map.plmap)")
      .epilog(
          "outputs: trajectory.txt (TUM, every tracked frame, first camera's frame), trajectory_map.txt (the same in the\n"
          "map frame), keyframes.txt, map_frame.yaml, sparse_map.ply, stats.json, config.yaml,\n"
          "map.plmap (the map, for --map; written atomically, also after Ctrl-C)\n"
          "and the dense products (unless --no-dense; see plslam export): dense_cloud.pcd, dense_cloud_semantic.ply,\n"
          "octomap.bt, octomap_semantic.ot, grid.pgm + grid.yaml, dense_products.json\n"
          "Every world-frame output but trajectory.txt and keyframes.txt is in the map frame (z up, x forward,\n"
          "origin on the floor below the first camera; map_frame.yaml holds T_map_world).\n"
          "When the folder has groundtruth.txt, the ATE is printed and added to stats.json.\n"
          "Ctrl-C stops the run and still writes what it has.\n\n"
          "example: plslam run --dataset rgbd_dataset_freiburg1_xyz --calib calib/tum_freiburg1.xml --out maps/fr1_xyz");
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));

  SystemOptions options;
  OptionTable table;
  std::optional<LoadedMap> loaded;
  if (args.has("localize") && !args.has("map")) throw ConfigError("plslam run: --localize needs --map FILE");
  if (!args.has("calib") && !args.has("map")) throw ConfigError("plslam run: --calib is required (or --map)");
  if (args.has("map")) {
    // The map's own configuration first (same features and tracking), then --config over it.
    loaded = loadMap(args.str("map"));
    bindOptions(&table, &options);
    if (!loaded->config_yaml.empty())
      table.apply(parseYamlSubset(loaded->config_yaml, args.str("map")), args.str("map") + " (saved configuration)");
    if (args.has("config")) table.apply(parseYamlSubset(readTextFile(args.str("config")), args.str("config")), args.str("config"));
    options.tracker.localization_only = args.has("localize");
  } else {
    loadRunConfig(args.has("config") ? args.str("config") : std::string(), &options, &table);
  }
  if (args.has("sequential")) options.sequential = true;
  if (args.has("no-lines")) options.use_lines = false;
  if (args.has("no-dynamic")) options.dynamic.enabled = false;
  if (args.has("no-loop")) options.use_loop = false;
  const std::string segmenter = args.str("segmenter");
  if (segmenter == "none" || segmenter == "replay") {
    options.segmenter.kind = parseSegmenterKind(segmenter);
  } else {
    options.segmenter.kind = SegmenterKind::kYolo;
    options.segmenter.yolo.model_path = segmenter;
  }
  options.segmenter.classes_file = args.str("classes");
  if (args.has("dynamic-classes")) {
    std::vector<std::string> names;
    std::stringstream list(args.str("dynamic-classes"));
    for (std::string name; std::getline(list, name, ',');)
      if (!name.empty()) names.push_back(name);
    options.segmenter.dynamic_classes = names;
  }
  options.segmenter.allow_missing_model = args.has("allow-missing-model");
  if (args.has("print-config")) {
    std::cout << table.toYaml("plslam run: effective configuration");
    return 0;
  }

  const PinholeCamera camera = args.has("calib") ? loadCameraFile(args.str("calib")) : loaded->camera;
  if (loaded && (camera.width != loaded->camera.width || camera.height != loaded->camera.height ||
                 camera.fx != loaded->camera.fx || camera.fy != loaded->camera.fy))
    std::fprintf(stderr, "[run] warning: --calib differs from the camera the map was built with\n");
  DatasetOptions dopt;
  dopt.max_frames = args.integer("max-frames", 0, 100000000);
  TumDataset dataset = TumDataset::open(args.str("dataset"), camera, dopt);
  if (options.segmenter.kind == SegmenterKind::kReplay) {
    if (dataset.instanceLabels().empty() && dataset.listReport().masks_listed == 0)
      throw ConfigError("plslam run: --segmenter replay needs a folder with masks.txt (plslam synth writes one): " +
                        dataset.dir());
    options.segmenter.replay_labels = replayLabels(dataset);
  }
  const std::string out = args.str("out");
  // Refuse an unusable output folder before the run, not after it.
  {
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (!std::filesystem::is_directory(out))
      throw IoError(out + ": cannot create the output folder" + (ec ? " (" + ec.message() + ")" : std::string()));
  }

  System slam(camera, options, loaded ? std::move(loaded->map) : Map());
  slam.start();
  const bool progress = !args.has("quiet");
  FeedResult fed;
  {
    SigintGuard sigint;
    ProgressLine line("run");
    fed = feedFrames(&slam, &dataset, [&](const FeedProgress& p) {
      if (!progress) return;
      line.update("frame %zu/%zu  tracked %d  keyframes %zu  %.1f frames/s", p.done, p.total, p.tracked, p.keyframes,
                  p.done / std::max(p.seconds, 1e-9));
    }, 500, args.has("realtime") ? Pace::kRecorded : Pace::kAsFastAsPossible);
    line.done();
  }
  if (fed.interrupted) std::fprintf(stderr, "[run] interrupted: finishing and writing what there is\n");
  slam.finish();
  const std::string skipped = skippedFramesText(dataset);
  // A run that tracked nothing has no result: say why and leave the output folder as it was.
  if (fed.tracked == 0) {
    if (fed.interrupted) {
      std::fprintf(stderr, "[run] interrupted before any frame was tracked: no outputs written to %s\n", out.c_str());
      return 130;
    }
    if (fed.fed == 0)
      throw DataError(str(dataset.dir(), ": none of the ", dataset.size(), " frames could be loaded (", skipped,
                          "); see the messages above for each file"));
    throw DataError(str(dataset.dir(), ": none of the ", fed.fed, " frames loaded could be tracked (last reason: ",
                        fed.last_failure, ")", skipped.empty() ? "" : "; skipped: " + skipped));
  }

  const RunEvaluation evaluation = evaluateRun(dataset, slam.trajectory());
  const std::string ate_line = evaluation.text();
  // The dense products first: the floor of their cloud gives the map frame of every output
  // (a loaded map keeps its own, so that its sessions share one map frame).
  std::optional<MapFrame> frame = loaded ? loaded->frame : std::nullopt;
  const bool dense = !args.has("no-dense") && options.dense.enabled;
  const bool dense_done = !dense || writeDenseMaps(slam.map(), camera, options.dense, {}, out, progress,
                                                   frame ? &*frame : nullptr, &frame);
  writeRunOutputs(out, slam, table.toYaml("plslam run: effective configuration"), runStatsExtra(dataset, evaluation),
                  args.has("save-map") ? args.str("save-map") : std::string(), frame ? &*frame : nullptr);

  const RunStats st = slam.stats();
  const Summary tms = summarize(st.tracking_ms);
  std::printf("frames %d, tracked %d (%.1f%%), keyframes %d, lost %d, map %d points %d lines\n", st.frames, st.tracked,
              st.frames ? 100.0 * st.tracked / st.frames : 0.0, st.keyframes, st.lost_events, st.map_points, st.map_lines);
  std::printf("tracking %.1f ms/frame median, %.1f p95, %.1f max; line reconstruction rate: fitting %.3f, endpoints %.3f\n",
              tms.median, tms.p95, tms.max, st.line_rate_fitting, st.line_rate_endpoints);
  if (!skipped.empty()) std::printf("skipped %d of %zu frames: %s\n", dataset.skippedTotal(), dataset.size(), skipped.c_str());
  if (!ate_line.empty()) std::printf("%s\n", ate_line.c_str());
  std::printf("outputs: %s\n", out.c_str());
  if (!dense_done) return 130;
  return fed.interrupted ? 130 : 0;
}

}  // namespace

Command makeRunCommand() { return {"run", "SLAM over a recorded RGB-D folder (TUM layout)", runRun}; }

}  // namespace plslam::cli
