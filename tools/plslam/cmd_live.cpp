// plslam live: SLAM on frames straight from the camera (Intel RealSense through ViSP), or
// from a recorded folder played at camera rate (--fake), with the outputs of plslam run.
#include <cstdio>
#include <memory>

#include "progress_line.h"
#include "camera/camera_file.h"
#include "capture/frame_grabber.h"
#include "commands.h"
#include "grabber_source.h"
#include "core/error.h"
#include "core/log.h"
#include "dense_cli.h"
#include "live/live_loop.h"
#include "session/live_maps.h"
#include "run_session.h"
#include "system/run_outputs.h"
#include "system/system.h"

namespace plslam::cli {

namespace {

int runLiveCommand(int argc, char** argv) {
  Args args("live", "Point-line RGB-D SLAM on the live camera (Intel RealSense D435i through ViSP).");
  args.option("out", "output folder (created if needed)", "", true)
      .option("calib", "camera file (ViSP XML) to use instead of the device's intrinsics")
      .option("record", "also record every grabbed frame as a TUM folder here")
      .option("duration", "stop after this many seconds (0: until Ctrl-C)", "0")
      .option("max-frames", "stop after this many grabbed frames (0: no limit)", "0")
      .option("queue", "frames waiting for tracking before the oldest is dropped", "2")
      .flag("no-drop", "never drop frames: the grabber waits for tracking")
      .flag("sequential", "deterministic single-thread System; implies --no-drop, so plslam run --sequential on the "
                          "--record folder gives the same trajectory")
      .flag("no-dense", "no dense products (cloud, OctoMaps, 2D grid), neither while running nor at the end")
      .option("fake", "testing: play this recorded TUM folder (with camera.xml) at camera rate instead of the camera")
      .option("fake-speed", "testing: playback speed of --fake (1 = its stamps, 0 = as fast as it is read)", "1")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .flag("quiet", "no progress line")
      .option("save-map", "where to write the map at the end (default: <out>/map.plmap)");
  addRunSwitches(&args);  // the same as plslam run's
  args.epilog(
          "outputs: as plslam run (trajectory.txt, keyframes.txt, sparse_map.ply, stats.json with the live_* frame "
          "counts, config.yaml,\nand unless --no-dense the dense products, updated while it runs every "
          "dense.live_every_keyframes keyframes or\ndense.live_every_s seconds and written again at the end).\n"
          "Ctrl-C stops and still writes what there is.\n"
          "Needs ViSP built with librealsense2; without it (Debian's ViSP) this prints why and exits with status 2.\n\n"
          "example: plslam live --out maps/office --record recordings/office --duration 60");
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));

  // The switches as plslam run's (session/run_config.h): the calibration keys are loaded there.
  RunConfig config = makeRunConfig(runSwitches(args), "plslam live: effective configuration");
  if (config.options.segmenter.kind == SegmenterKind::kReplay)
    throw ConfigError("plslam live: the replay segmenter (--segmenter replay, segmenter.backend) replays a recorded folder's masks: use plslam run on it");
  const SystemOptions& options = config.options;
  LiveOptions live;
  live.drop_frames = !(args.has("no-drop") || args.has("sequential"));
  live.queue = args.integer("queue", 1, 1000);
  live.duration_s = args.number("duration");
  live.max_frames = args.integer("max-frames", 0, 100000000);
  if (args.has("record")) live.record_dir = args.str("record");

  std::unique_ptr<FrameGrabber> grabber = openGrabber(args);
  const PinholeCamera device = grabber->intrinsics();
  PinholeCamera camera = device;
  if (args.has("calib")) {
    camera = loadCameraFile(args.str("calib"));
    checkImageSize(camera, device.width, device.height, grabber->name());
  }
  // The recording keeps the device's depth scale, so its depth PNGs are the sensor's values.
  PinholeCamera recording = camera;
  recording.depth_scale = device.depth_scale;

  const std::string out = args.str("out");
  if (config.map && (camera.width != config.map->camera.width || camera.height != config.map->camera.height))
    throw ConfigError(str("plslam live: the camera's images are ", camera.width, "x", camera.height,
                          ", the map was built from ", config.map->camera.width, "x", config.map->camera.height));
  System slam(camera, options, config.map ? std::move(config.map->map) : Map());
  // A saved map keeps its own frame, so that its sessions share one map frame.
  std::optional<MapFrame> frame = config.map ? config.map->frame : std::nullopt;
  const bool dense = !args.has("no-dense") && options.dense.enabled;
  std::unique_ptr<LiveMaps> maps = dense ? makeLiveMaps(&slam, out, frame ? &*frame : nullptr) : nullptr;
  slam.start();
  if (maps) maps->start();
  const bool progress = !args.has("quiet");
  LiveStats stats;
  {
    SigintGuard sigint;
    ProgressLine line("live");
    stats = runLive(
        grabber.get(), &slam, live, [] { return SigintGuard::interrupted(); },
        [&](const LiveProgress& p) {
          if (!progress) return;
          line.update("grabbed %d  processed %d  dropped %d  tracked %d  %.1f s", p.grabbed, p.processed, p.dropped,
                      p.tracked, p.seconds);
        },
        500, &recording);
    line.done();
  }
  grabber->close();
  if (maps) maps->stop();
  slam.finish();
  // The final products in the saved map's frame, else the one the maps while running settled
  // on (as plslam run).
  if (maps && !frame) frame = maps->settledFrame();
  Json stats_extra = liveStatsJson(stats);
  if (maps) stats_extra.update(liveMapsStatsJson(maps->stats()));
  if (dense && !slam.map().keyframes().empty())
    writeDenseMaps(slam.map(), camera, options.dense, {}, out, progress, frame ? &*frame : nullptr, &frame);
  writeRunOutputs(out, slam, config.config_yaml, stats_extra, args.str("save-map"), frame ? &*frame : nullptr);

  const RunStats st = slam.stats();
  const Summary tms = summarize(st.tracking_ms);
  std::printf("frames grabbed %d, processed %d, dropped %d (%s); tracked %d, keyframes %d, lost %d\n", stats.grabbed,
              stats.processed, stats.dropped, toString(stats.stop), st.tracked, st.keyframes, st.lost_events);
  std::printf("tracking %.1f ms/frame median, %.1f p95; %.1f s, %.1f frames/s processed\n", tms.median, tms.p95,
              stats.seconds, stats.seconds > 0 ? stats.processed / stats.seconds : 0.0);
  if (!live.record_dir.empty()) std::printf("recorded %d frames: %s\n", stats.recorded, live.record_dir.c_str());
  std::printf("outputs: %s\n", out.c_str());
  return stats.stop == LiveStop::kInterrupted ? 130 : 0;
}

}  // namespace

Command makeLiveCommand() { return {"live", "SLAM on the live RealSense camera (or a folder played as one)", runLiveCommand}; }

}  // namespace plslam::cli
