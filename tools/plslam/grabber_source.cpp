#include "grabber_source.h"

#include "capture/replay_grabber.h"
#include "core/error.h"

namespace plslam::cli {

std::unique_ptr<FrameGrabber> openGrabber(const Args& args) {
  std::unique_ptr<FrameGrabber> grabber;
  if (args.has("fake")) {
    ReplayOptions ropt;
    ropt.speed = args.number("fake-speed");
    if (ropt.speed < 0) throw ConfigError("--fake-speed must be >= 0 (0: as fast as it is read)");
    grabber = std::make_unique<ReplayGrabber>(args.str("fake"), ropt);
  } else {
    grabber = makeRealSenseGrabber();  // ConfigError naming what is missing when unavailable
  }
  grabber->open();
  return grabber;
}

}  // namespace plslam::cli
