// plslam run: SLAM over a recorded RGB-D folder (TUM layout), writing the trajectory,
// keyframes, sparse map, statistics and effective configuration.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "camera/camera_file.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "io/dataset.h"
#include "run_session.h"
#include "system/run_outputs.h"
#include "system/system.h"

namespace plslam::cli {

namespace {

int runRun(int argc, char** argv) {
  Args args("run", "Point-line RGB-D SLAM over a recorded folder (TUM RGB-D layout, ICL-NUIM, or plslam synth).");
  args.option("dataset", "folder with rgb.txt and depth.txt (or associations.txt)", "", true)
      .option("calib", "camera file (ViSP XML, see calib/)", "", true)
      .option("out", "output folder (created if needed)", "", true)
      .option("config", "YAML run options (plslam run --print-config shows every key)")
      .option("max-frames", "process only the first N frames (0 = all)", "0")
      .flag("sequential", "deterministic single-thread order (identical output across runs)")
      .flag("no-lines", "points only: no line features")
      .option("segmenter", "instance masks: none, replay (the folder's masks/, as plslam synth writes), or a YOLOv8-seg .onnx file",
              "none")
      .option("classes", "class names file, one a line, in the model's order (default: the COCO names)")
      .option("dynamic-classes", "comma-separated class names that may move (default: person, animals, vehicles)")
      .flag("allow-missing-model", "if the model cannot be used, warn and go on with the geometric checks only")
      .flag("no-dynamic", "no rejection of moving objects at all")
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
  loadRunConfig(args.has("config") ? args.str("config") : std::string(), &options, &table);
  if (args.has("sequential")) options.sequential = true;
  if (args.has("no-lines")) options.use_lines = false;
  if (args.has("no-dynamic")) options.dynamic.enabled = false;
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

  const PinholeCamera camera = loadCameraFile(args.str("calib"));
  DatasetOptions dopt;
  dopt.max_frames = args.integer("max-frames", 0, 100000000);
  TumDataset dataset = TumDataset::open(args.str("dataset"), camera, dopt);
  if (options.segmenter.kind == SegmenterKind::kReplay) {
    if (dataset.instanceLabels().empty() && dataset.listReport().masks_listed == 0)
      throw ConfigError("plslam run: --segmenter replay needs a folder with masks.txt (plslam synth writes one): " +
                        dataset.dir());
    for (const InstanceLabel& l : dataset.instanceLabels())
      options.segmenter.replay_labels.push_back({l.instance_id, l.class_id, l.class_name});
  }
  const std::string out = args.str("out");

  System slam(camera, options);
  slam.start();
  const bool progress = !args.has("quiet");
  FeedResult fed;
  {
    SigintGuard sigint;
    fed = feedFrames(&slam, &dataset, [&](const FeedProgress& p) {
      if (!progress) return;
      std::fprintf(stderr, "\r[run] frame %zu/%zu  tracked %d  keyframes %zu  %.1f frames/s  ", p.done, p.total,
                   p.tracked, p.keyframes, p.done / std::max(p.seconds, 1e-9));
      std::fflush(stderr);
    });
    if (progress) std::fprintf(stderr, "\n");
  }
  if (fed.interrupted) std::fprintf(stderr, "[run] interrupted: finishing and writing what there is\n");
  slam.finish();

  const RunEvaluation evaluation = evaluateRun(dataset, slam.trajectory());
  const std::string ate_line = evaluation.text();
  writeRunOutputs(out, slam, table.toYaml("plslam run: effective configuration"), runStatsExtra(dataset, evaluation));

  const RunStats st = slam.stats();
  const Summary tms = summarize(st.tracking_ms);
  std::printf("frames %d, tracked %d (%.1f%%), keyframes %d, lost %d, map %d points %d lines\n", st.frames, st.tracked,
              st.frames ? 100.0 * st.tracked / st.frames : 0.0, st.keyframes, st.lost_events, st.map_points, st.map_lines);
  std::printf("tracking %.1f ms/frame median, %.1f p95; line reconstruction rate: fitting %.3f, endpoints %.3f\n",
              tms.median, tms.p95, st.line_rate_fitting, st.line_rate_endpoints);
  if (!ate_line.empty()) std::printf("%s\n", ate_line.c_str());
  std::printf("outputs: %s\n", out.c_str());
  return fed.interrupted ? 130 : 0;
}

}  // namespace

Command makeRunCommand() { return {"run", "SLAM over a recorded RGB-D folder (TUM layout)", runRun}; }

}  // namespace plslam::cli
