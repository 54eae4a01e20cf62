#include "capture/frame_grabber.h"

#include <visp3/core/vpConfig.h>

#include <string>

namespace plslam {

bool realSenseAvailable() {
#if defined(VISP_HAVE_REALSENSE2)
  return true;
#else
  return false;
#endif
}

std::string realSenseUnavailableMessage() {
  if (realSenseAvailable()) return "";
  return "live capture is unavailable: this plslam was built against a ViSP " + std::to_string(VISP_VERSION_MAJOR) +
         "." + std::to_string(VISP_VERSION_MINOR) + "." + std::to_string(VISP_VERSION_PATCH) +
         " without librealsense2 support (VISP_HAVE_REALSENSE2 is not defined; Debian's libvisp-dev is built "
         "without it). To capture from an Intel RealSense: install librealsense2 (librealsense2-dev from Intel's "
         "apt repository, or built from source), build ViSP from source with it (cmake -DUSE_REALSENSE2=ON; "
         "then its vpConfig.h defines VISP_HAVE_REALSENSE2), then rebuild plslam with "
         "-DVISP_DIR=<that ViSP's build or install folder>. Meanwhile, record with another tool into a TUM folder "
         "and use `plslam run`, or `plslam live --fake DIR` to exercise the live path on a recorded folder.";
}

}  // namespace plslam
