#include "frame_source_open.h"

#include "core/error.h"
#include "core/log.h"
#ifdef PLSLAM_WITH_ROS
#include "ros1/bag_source.h"
#endif

namespace plslam::cli {

bool isBagPath(const std::string& path) { return path.size() > 4 && path.compare(path.size() - 4, 4, ".bag") == 0; }

namespace {

OpenedSource openBag(const std::string& path, const PinholeCamera* camera, const DatasetOptions& options) {
#ifdef PLSLAM_WITH_ROS
  ros1::BagOptions bopt;
  bopt.max_difference_s = options.max_difference_s;
  bopt.max_frames = options.max_frames;
  bopt.groundtruth_file = options.groundtruth_file;
  std::unique_ptr<ros1::BagSource> bag = ros1::BagSource::open(path, bopt);
  PinholeCamera used = bag->camera();
  if (camera) {
    if (camera->width != used.width || camera->height != used.height)
      throw ConfigError(str(path, ": the bag's images are ", used.width, "x", used.height, ", the camera file's ",
                            camera->width, "x", camera->height));
    used = *camera;
  }
  return {std::move(bag), used};
#else
  (void)camera;
  (void)options;
  throw ConfigError(path + ": this plslam was built without ROS, so it cannot read bags (install the ROS 1 packages "
                           "with tools/setup.sh and rebuild)");
#endif
}

}  // namespace

OpenedSource openFrameSource(const std::string& path, const PinholeCamera* camera, const DatasetOptions& options) {
  if (isBagPath(path)) return openBag(path, camera, options);
  if (!camera) throw ConfigError("plslam run: --calib is required for a folder (or --map)");
  return {std::make_unique<TumDataset>(TumDataset::open(path, *camera, options)), *camera};
}

}  // namespace plslam::cli
