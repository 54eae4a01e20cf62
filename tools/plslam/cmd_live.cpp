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
#include "live/live_loop.h"
#include "mapping_session.h"
#include "run_session.h"
#include "system/run_outputs.h"
#include "system/system.h"

namespace plslam::cli {

namespace {

Args liveArgs() {
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
  return args;
}

LiveOptions liveOptions(const Args& args) {
  LiveOptions live;
  live.drop_frames = !(args.has("no-drop") || args.has("sequential"));
  live.queue = args.integer("queue", 1, 1000);
  live.duration_s = args.number("duration");
  live.max_frames = args.integer("max-frames", 0, 100000000);
  if (args.has("record")) live.record_dir = args.str("record");
  return live;
}

// The camera SLAM runs with: the device's intrinsics, or --calib's for the same image size;
// a map to start from must have been built at that size.
PinholeCamera liveCamera(const Args& args, const FrameGrabber& grabber, const RunConfig& config) {
  const PinholeCamera device = grabber.intrinsics();
  PinholeCamera camera = device;
  if (args.has("calib")) {
    camera = loadCameraFile(args.str("calib"));
    checkImageSize(camera, device.width, device.height, grabber.name());
  }
  if (config.map && (camera.width != config.map->camera.width || camera.height != config.map->camera.height))
    throw ConfigError(str("plslam live: the camera's images are ", camera.width, "x", camera.height,
                          ", the map was built from ", config.map->camera.width, "x", config.map->camera.height));
  return camera;
}

void printLiveSummary(const LiveStats& stats, const System& slam, const LiveOptions& live, const std::string& out) {
  const RunStats st = slam.stats();
  const Summary tms = summarize(st.tracking_ms);
  std::printf("frames grabbed %d, processed %d, dropped %d (%s); tracked %d, keyframes %d, lost %d\n", stats.grabbed,
              stats.processed, stats.dropped, toString(stats.stop), st.tracked, st.keyframes, st.lost_events);
  std::printf("tracking %.1f ms/frame median, %.1f p95; %.1f s, %.1f frames/s processed\n", tms.median, tms.p95,
              stats.seconds, stats.seconds > 0 ? stats.processed / stats.seconds : 0.0);
  if (!live.record_dir.empty()) std::printf("recorded %d frames: %s\n", stats.recorded, live.record_dir.c_str());
  std::printf("outputs: %s\n", out.c_str());
}

int runLiveCommand(int argc, char** argv) {
  Args args = liveArgs();
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));

  // The switches as plslam run's (session/run_config.h): the calibration keys are loaded there.
  RunConfig config = makeRunConfig(runSwitches(args), "plslam live: effective configuration");
  if (config.options.segmenter.kind == SegmenterKind::kReplay)
    throw ConfigError("plslam live: the replay segmenter (--segmenter replay, segmenter.backend) replays a recorded folder's masks: use plslam run on it");
  const LiveOptions live = liveOptions(args);
  std::unique_ptr<FrameGrabber> grabber = openGrabber(args);
  const PinholeCamera camera = liveCamera(args, *grabber, config);
  // The recording keeps the device's depth scale, so its depth PNGs are the sensor's values.
  PinholeCamera recording = camera;
  recording.depth_scale = grabber->intrinsics().depth_scale;

  const std::string out = args.str("out");
  SigintGuard sigint;  // as in plslam run: made before the session, so Ctrl-C never cuts its end short
  MappingSession session(camera, &config, out, !args.has("no-dense") && config.options.dense.enabled);
  System& slam = session.slam();
  session.start();
  const bool progress = !args.has("quiet");
  LiveStats stats;
  {
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
  session.stop();
  session.writeOutputs(liveStatsJson(stats), args.str("save-map"), progress);
  printLiveSummary(stats, slam, live, out);
  return stats.stop == LiveStop::kInterrupted ? 130 : 0;
}

}  // namespace

Command makeLiveCommand() { return {"live", "SLAM on the live RealSense camera (or a folder played as one)", runLiveCommand}; }

}  // namespace plslam::cli
