#include "dense_cli.h"

#include <cstdio>

#include "progress_line.h"
#include "run_session.h"

namespace plslam::cli {

bool writeDenseMaps(const Map& map, const PinholeCamera& camera, const DenseOptions& options,
                    const DenseSelection& what, const std::string& dir, bool progress) {
  SigintGuard sigint;
  ProgressLine line("dense");
  DenseProducts products = buildDenseProducts(map, camera, options, what, [&](const std::string& stage, size_t done,
                                                                              size_t total) {
    if (progress) line.update("%s: keyframe %zu/%zu", stage.c_str(), done, total);
    return !SigintGuard::interrupted();
  });
  line.done();
  if (products.cancelled) std::fprintf(stderr, "[dense] interrupted: no dense product written\n");
  const std::vector<WrittenFile> files = writeDenseProducts(dir, products, what, options);
  std::printf("dense: %d keyframes (%d with a cloud, %zu points), fused cloud %zu points\n", products.keyframes,
              products.keyframes_with_cloud, products.keyframe_points, products.cloud.size());
  for (const DenseCost& c : products.costs)
    std::printf("dense %-16s %8.2f s  peak RSS %7.1f MB (%.1f MB before)\n", c.step.c_str(), c.seconds, c.peak_rss_mb,
                c.start_rss_mb);
  if (products.grid.width > 0)
    std::printf("dense floor: %s; grid %dx%d cells of %.3f m: %d occupied, %d free, %d unknown\n",
                products.floor.method.c_str(), products.grid.width, products.grid.height, products.grid.resolution,
                products.grid.count(OccupancyGrid::kOccupied), products.grid.count(OccupancyGrid::kFree),
                products.grid.count(OccupancyGrid::kUnknown));
  for (const WrittenFile& f : files) std::printf("dense file %s: %ju bytes\n", f.path.c_str(), f.bytes);
  return !products.cancelled;
}

}  // namespace plslam::cli
