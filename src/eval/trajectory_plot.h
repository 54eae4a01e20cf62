// A picture of an evaluated trajectory: the aligned estimate over the ground truth seen
// from above, the estimate coloured by its ATE error (colour bar in metres), a scale bar,
// and the ATE RMSE in the title. "Above" is the plane of the two axes along which the
// ground truth extends most (x-y for most handheld sequences); the legend says which.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"

namespace plslam {

struct PlotOptions {
  int width = 1000;    ///< image width, pixels
  int height = 800;    ///< image height, pixels
  std::string title;   ///< second title line (e.g. the estimate's file name); empty: none
};

/// Renders the plot as a CV_8UC3 image. `ate` must come from computeAte(gt, est, ...).
/// Throws ConfigError for an image smaller than 320x240.
cv::Mat renderTrajectoryPlot(const Trajectory& gt, const Trajectory& est, const AteResult& ate,
                             const PlotOptions& options = {});

/// Renders and writes the plot (PNG, or any format OpenCV knows by the file's extension),
/// atomically. Throws IoError naming `path` when it cannot be written.
void plotTrajectories(const std::string& path, const Trajectory& gt, const Trajectory& est, const AteResult& ate,
                      const PlotOptions& options = {});

}  // namespace plslam
