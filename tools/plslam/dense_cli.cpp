#include "dense_cli.h"

#include <cstdio>

#include "progress_line.h"
#include "run_session.h"

namespace plslam::cli {

bool writeDenseMaps(const Map& map, const PinholeCamera& camera, const DenseOptions& options,
                    const DenseSelection& what, const std::string& dir, bool progress, const MapFrame* given,
                    std::optional<MapFrame>* used) {
  SigintGuard sigint;
  ProgressLine line("dense");
  DenseProducts products = buildDenseProducts(map, camera, options, what, [&](const std::string& stage, size_t done,
                                                                              size_t total) {
    if (progress) line.update("%s: keyframe %zu/%zu", stage.c_str(), done, total);
    return !SigintGuard::interrupted();
  }, given);
  line.done();
  if (products.cancelled) std::fprintf(stderr, "[dense] interrupted: no dense product written\n");
  const std::vector<WrittenFile> files = writeDenseProducts(dir, products, what, options);
  std::printf("dense: %d keyframes (%d with a cloud, %zu points), fused cloud %zu points\n", products.keyframes,
              products.keyframes_with_cloud, products.keyframe_points, products.cloud.size());
  for (const DenseCost& c : products.costs)
    std::printf("dense %-16s %8.2f s  peak RSS %7.1f MB (%.1f MB before)\n", c.step.c_str(), c.seconds, c.peak_rss_mb,
                c.start_rss_mb);
  if (!products.frame.floor_method.empty()) {
    if (used) *used = products.frame;
    std::printf("map frame: floor %s (%s points%s), first camera %.3f m above the floor\n",
                products.frame.floor_method.c_str(), products.frame.floor_source.c_str(),
                given ? ", from the map file" : "", products.frame.cameraHeight());
  }
  if (products.grid.width > 0)
    std::printf("dense grid %dx%d cells of %.3f m: %d occupied, %d free, %d unknown\n",
                products.grid.width, products.grid.height, products.grid.resolution,
                products.grid.count(OccupancyGrid::kOccupied), products.grid.count(OccupancyGrid::kFree),
                products.grid.count(OccupancyGrid::kUnknown));
  for (const WrittenFile& f : files) std::printf("dense file %s: %ju bytes\n", f.path.c_str(), f.bytes);
  return !products.cancelled;
}

}  // namespace plslam::cli
