// The whitened residual terms of point and line observations, built the same way for the
// pose-only optimiser and the bundle adjuster (internal to optim).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "optim/cost_functions.h"
#include "optim/measurement.h"

namespace plslam::optim_internal {

struct ObservationTerms {
  std::vector<PointTerm<2>> mono;  ///< per point: pixel residual (used when !has_depth)
  std::vector<PointTerm<3>> rgbd;  ///< per point: pixel + depth residual (used when has_depth)
  std::vector<bool> has_depth;     ///< per point: the model trusts its depth
  std::vector<LineTerm> lines;     ///< per line observation
  std::vector<bool> line_ok;       ///< per line: the observed segment defines a line

  ObservationTerms(size_t points, size_t line_count)
      : mono(points), rgbd(points), has_depth(points, false), lines(line_count), line_ok(line_count, false) {}

  void setPoint(size_t i, const Intrinsics& K, const MeasurementModel& model, const Eigen::Vector2d& uv, int octave,
                double depth) {
    const double inv_sigma = 1.0 / model.pixelSigma(octave);
    has_depth[i] = model.hasDepth(depth);
    if (has_depth[i])
      rgbd[i] = {K, uv, inv_sigma, depth, 1.0 / model.depthSigma(depth), model.min_depth};
    else
      mono[i] = {K, uv, inv_sigma, 0.0, 0.0, model.min_depth};
  }

  void setLine(size_t i, const Intrinsics& K, const MeasurementModel& model, const Eigen::Vector2d& p,
               const Eigen::Vector2d& q, int octave) {
    LineTerm& t = lines[i];
    line_ok[i] = normalisedLine(p, q, &t.l);
    t.K = K, t.inv_sigma = 1.0 / model.pixelSigma(octave), t.min_depth = model.min_depth;
  }
};

}  // namespace plslam::optim_internal
