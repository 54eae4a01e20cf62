// Opens what `plslam run --dataset` names: a ROS bag (a file ending in .bag; read by the
// ros1 module, present only when plslam was built with ROS) or a TUM-layout folder.
#pragma once

#include <memory>
#include <string>

#include "camera/pinhole_camera.h"
#include "io/dataset.h"
#include "io/frame_source.h"

namespace plslam::cli {

struct OpenedSource {
  std::unique_ptr<FrameSource> source;
  PinholeCamera camera;  ///< the camera the frames are read with
};

/// True when `path` names a bag rather than a folder.
bool isBagPath(const std::string& path);

/// Opens `path`. `camera` (may be null for a bag, which has its camera_info) is the camera
/// file's; for a bag a given camera must have the bag's image size. Throws ConfigError
/// when a folder has no camera or a bag is given to a build without ROS.
OpenedSource openFrameSource(const std::string& path, const PinholeCamera* camera, const DatasetOptions& options);

}  // namespace plslam::cli
