// Local mapping: for each new keyframe, 3D map lines by fitting depth samples along its
// unmatched segments (the endpoint method runs beside it only to measure the average
// reconstruction rate of both), a local bundle adjustment of the keyframe, its covisible
// keyframes, their points and lines (Ceres), and culling of landmarks that tracking
// rarely finds again.
//
// Thread safety: processKeyframe() runs on one thread (the mapping thread, or the
// caller's in sequential mode); it takes the map's mutex only to read a snapshot and to
// write results back, never while Ceres runs.
#pragma once

#include <mutex>
#include <opencv2/core.hpp>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "mapping/line_reconstruction.h"
#include "optim/bundle_adjuster.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindLocalMapperOptions (mapping/option_keys.cpp). `plslam run --print-config` lists them.
struct LocalMapperOptions {
  bool use_lines = true;           ///< build and optimise 3D lines
  bool local_ba = true;
  int ba_keyframes = 8;
  int ba_fixed_keyframes = 16;
  int min_covisible_points = 15;
  double cull_found_ratio = 0.25;
  int cull_min_visible = 6;
  int cull_single_after = 3;
  LineFitOptions line_fit;         ///< line fitting (and endpoint method) parameters
  BundleAdjusterOptions ba = mappingBundleOptions();  ///< local bundle adjustment

  /// Throws ConfigError naming the `mapper.` key of the first value out of range (the mapper
  /// checks on construction).
  void validate() const;

  /// Depth weighted as in every SLAM solver (kSolverDepthSigmaCoeff).
  static BundleAdjusterOptions mappingBundleOptions() {
    BundleAdjusterOptions o;
    o.model.depth_sigma_coeff = kSolverDepthSigmaCoeff;
    return o;
  }
};

/// Binds the mapper.* keys (mapping/option_keys.cpp).
void bindLocalMapperOptions(OptionTable* table, LocalMapperOptions* options);

/// Figures the mapper keeps for the run's statistics.
struct MapperStats {
  LineReconstructionRate rate_fitting;    ///< 3D segments built / 2D segments used, per keyframe, by fitting
  LineReconstructionRate rate_endpoints;  ///< the same by endpoint back-projection
  int lines_created = 0;
  int points_culled = 0, lines_culled = 0;
  int ba_runs = 0;
  int ba_dropped = 0;  ///< results dropped because a loop correction landed during the solve
  std::vector<double> ba_ms;
};

class LocalMapper {
 public:
  LocalMapper(Map* map, PinholeCamera camera, LocalMapperOptions options);
  /// `depth_m` is the keyframe's depth image (metres, NaN = none), needed for line fitting.
  void processKeyframe(Id keyframe, const cv::Mat& depth_m);
  /// A copy: safe from any thread while the mapping thread runs.
  MapperStats stats() const {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    return stats_;
  }

 private:
  void createLines(Id keyframe, const cv::Mat& depth_m);
  void localBundleAdjustment(Id keyframe);
  void cull(Id keyframe);

  Map* map_;
  PinholeCamera camera_;
  LocalMapperOptions options_;
  BundleAdjuster adjuster_;
  mutable std::mutex stats_mutex_;  // guards stats_ (read by System::stats() mid-run)
  MapperStats stats_;
};

}  // namespace plslam
