// Trajectory accuracy exactly as docs/BENCHMARK.md defines it (the TUM RGB-D benchmark's
// evaluate_ate.py and evaluate_rpe.py --fixed_delta):
//
//   association  estimate/ground-truth stamps closer than max_difference (0.02 s), greedily
//                smallest difference first, each stamp once, sorted (io/associate.h)
//   ATE          rigid alignment of the associated estimate positions onto the ground truth
//                (Horn / Umeyama without scale), errors ||R p_est + t - p_gt||
//   RPE          for every estimate pose i (all of them, associated or not), j = the estimate
//                pose closest to t_i + delta (skipped when j is the last pose); the ground
//                truth poses closest to t_i and t_j, skipped when either is farther than twice
//                the median ground-truth interval; E = (est_i^-1 est_j)^-1 (gt_i^-1 gt_j);
//                ||t(E)|| and acos(clamp((tr R(E) - 1) / 2)) in degrees
//
// Statistics are those of numpy: rmse, mean, median (mean of the middle two for an even
// count), population standard deviation, min, max.
#pragma once

#include <string>
#include <vector>

#include "core/se3.h"
#include "core/trajectory.h"
#include "io/associate.h"

namespace plslam {

struct EvalOptions {
  double max_difference_s = 0.02;  ///< association window, seconds (associate.py's default)
  double rpe_delta_s = 1.0;        ///< RPE window, seconds (drift per second)
};

/// Summary statistics of a list of errors (all zero when count == 0).
struct Stats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
  int count = 0;
};
Stats computeStats(const std::vector<double>& values);

/// Associated (ground truth, estimate) pairs: StampMatch::first indexes `gt`, ::second `est`.
std::vector<StampMatch> associate(const Trajectory& gt, const Trajectory& est, double max_difference_s = 0.02);

struct AteResult {
  Stats stats;                     ///< of `errors`, metres
  SE3 T_gt_est;                    ///< maps estimate positions onto the ground truth
  std::vector<StampMatch> pairs;   ///< the associated pairs (gt index, est index), by time
  std::vector<double> errors;      ///< per pair, metres
};
/// ATE over the given pairs. Throws DataError with fewer than 3 pairs.
AteResult computeAte(const Trajectory& gt, const Trajectory& est, const std::vector<StampMatch>& pairs);

struct RpeResult {
  Stats trans;             ///< translational error per window, metres
  Stats rot_deg;           ///< rotational error per window, degrees
  int pairs = 0;           ///< evaluated (i, j) pairs; 0 when the trajectories overlap less than delta
  double delta_s = 1.0;
};
/// RPE with a fixed delta in seconds (evaluate_rpe.py --fixed_delta --delta_unit s).
/// Needs both trajectories non-empty; yields pairs == 0 when no window fits.
RpeResult computeRpe(const Trajectory& gt, const Trajectory& est, double delta_s = 1.0);

struct EvalResult {
  std::string gt_name, est_name;  ///< labels (file names) for messages and reports
  int gt_poses = 0, est_poses = 0;
  AteResult ate;
  RpeResult rpe;
};
/// Association, ATE and RPE. Throws DataError naming both inputs when fewer than 3 pairs
/// are associated (no overlap in time, or trajectories of different sequences).
EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options = {},
                    const std::string& gt_name = "ground truth", const std::string& est_name = "estimate");
/// Reads both TUM files (io/trajectory_file.h) and evaluates them.
EvalResult evaluateFiles(const std::string& gt_path, const std::string& est_path, const EvalOptions& options = {});

/// One JSON object: {"pairs", "ate": {rmse, mean, median, std, min, max}, "rpe": {pairs,
/// trans_rmse, trans_mean, ..., rot_rmse_deg, rot_mean_deg, ...}, ...}; RPE values are null
/// when rpe.pairs == 0. Metres and degrees.
std::string toJson(const EvalResult& result);
/// A few lines of plain text for people.
std::string toText(const EvalResult& result);

}  // namespace plslam
