// plslam record: the live camera (Intel RealSense through ViSP) recorded as a TUM RGB-D
// folder that plslam run replays exactly, or (built with ROS) as a bag in TUM's layout.
#include <chrono>
#include <cstdio>
#include <memory>

#include "capture/frame_grabber.h"
#include "capture/tum_recorder.h"
#include "commands.h"
#include "grabber_source.h"
#include "core/error.h"
#include "core/log.h"
#include "run_session.h"
#ifdef PLSLAM_WITH_ROS
#include "ros1/bag_writer.h"
#endif

namespace plslam::cli {

namespace {

std::unique_ptr<FrameRecorder> openRecorder(const Args& args, const PinholeCamera& camera) {
  if (args.has("out") == args.has("bag")) throw ConfigError("plslam record: give one of --out DIR or --bag FILE.bag");
  if (args.has("out")) return std::make_unique<TumRecorder>(args.str("out"), camera);
#ifdef PLSLAM_WITH_ROS
  return std::make_unique<ros1::BagWriter>(args.str("bag"), camera);
#else
  throw ConfigError("plslam record --bag: this plslam was built without ROS (install the ROS 1 packages: tools/setup.sh)");
#endif
}

int runRecordCommand(int argc, char** argv) {
  Args args("record", "Record the live camera (Intel RealSense through ViSP) as a TUM RGB-D folder for plslam run.");
  args.option("out", "folder to create (rgb/, depth/, rgb.txt, depth.txt, camera.xml)")
      .option("bag", "instead of --out: a ROS 1 bag to write, TUM's layout (/camera/rgb/image_color, "
                     "/camera/depth/image in metres, /camera/rgb/camera_info); needs plslam built with ROS")
      .option("duration", "stop after this many seconds (0: until Ctrl-C)", "0")
      .option("max-frames", "stop after this many frames (0: no limit)", "0")
      .option("fake", "testing: record this TUM folder played at camera rate instead of the camera")
      .option("fake-speed", "testing: playback speed of --fake (1 = its stamps, 0 = as fast as it is read)", "1")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .epilog(
          "Needs ViSP built with librealsense2; without it (Debian's ViSP) this prints why and exits with status 2.\n\n"
          "example: plslam record --out recordings/office --duration 30 && "
          "plslam run --dataset recordings/office --calib recordings/office/camera.xml --out maps/office");
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));
  const double duration = args.number("duration");
  const int max_frames = args.integer("max-frames", 0, 100000000);

  std::unique_ptr<FrameGrabber> grabber = openGrabber(args);
  const std::unique_ptr<FrameRecorder> recorder = openRecorder(args, grabber->intrinsics());
  int frames = 0;
  bool interrupted = false;
  {
    SigintGuard sigint;
    const auto start = std::chrono::steady_clock::now();
    RgbdFrame frame;
    while (true) {
      if (SigintGuard::interrupted()) {
        interrupted = true;
        break;
      }
      if (max_frames > 0 && frames >= max_frames) break;
      if (duration > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= duration)
        break;
      if (!grabber->grab(&frame)) break;
      recorder->add(frame);
      ++frames;
    }
  }
  grabber->close();
  recorder->close();
  std::printf("recorded %d frames: %s\n", recorder->written(), recorder->location().c_str());
  return interrupted ? 130 : 0;
}

}  // namespace

Command makeRecordCommand() {
  return {"record", "Record the live RealSense camera as a TUM RGB-D folder or a ROS bag", runRecordCommand};
}

}  // namespace plslam::cli
