// plslam eval: ATE and RPE of an estimated trajectory against ground truth (docs: the
// definitions of BENCHMARK.md, as the TUM RGB-D benchmark's scripts compute them).
#include <iostream>

#include "commands.h"
#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "eval/trajectory_plot.h"
#include "io/trajectory_file.h"

namespace plslam::cli {

namespace {

int runEval(int argc, char** argv) {
  if (argc > 0 && std::string(argv[0]) == "loops") return runEvalLoops(argc - 1, argv + 1);
  if (argc > 0 && std::string(argv[0]) == "masks") return runEvalMasks(argc - 1, argv + 1);
  Args args("eval", "Absolute trajectory error (ATE) and relative pose error (RPE) of an estimate against ground truth.");
  args.option("gt", "ground-truth trajectory, TUM format", "", true)
      .option("est", "estimated trajectory, TUM format", "", true)
      .flag("json", "print one JSON object instead of the text summary")
      .option("plot", "also draw the aligned estimate over the ground truth into this PNG file")
      .option("max-difference", "largest stamp difference for associating poses, seconds", "0.02")
      .option("delta", "RPE window, seconds", "1.0")
      .epilog(
          "Association: stamps closer than --max-difference, greedily smallest difference first, each once.\n"
          "ATE: rigid alignment (no scale) of the associated positions, metres.\n"
          "RPE: fixed --delta, over all estimate poses, metres and degrees per window.\n"
          "JSON: {\"pairs\", \"ate\": {rmse, mean, median, std, min, max}, \"rpe\": {pairs, trans_rmse, trans_mean,\n"
          "       rot_rmse_deg, rot_mean_deg, ...}}\n\n"
          "example: plslam eval --gt groundtruth.txt --est trajectory.txt --plot ate.png");
  if (!args.parse(argc, argv)) return 0;

  EvalOptions options;
  options.max_difference_s = args.number("max-difference");
  options.rpe_delta_s = args.number("delta");
  if (options.max_difference_s <= 0) throw ConfigError("plslam eval: --max-difference must be positive");
  if (options.rpe_delta_s <= 0) throw ConfigError("plslam eval: --delta must be positive");

  const std::string gt_path = args.str("gt"), est_path = args.str("est");
  const Trajectory gt = readTumTrajectory(gt_path);
  const Trajectory est = readTumTrajectory(est_path);
  const EvalResult result = evaluate(gt, est, options, gt_path, est_path);

  if (args.has("plot")) {
    PlotOptions plot;
    plot.title = est_path + "  vs  " + gt_path;
    plotTrajectories(args.str("plot"), gt, est, result.ate, plot);
  }
  std::cout << (args.has("json") ? toJson(result) : toText(result));
  if (args.has("plot") && !args.has("json")) std::cout << "plot: " << args.str("plot") << "\n";
  return 0;
}

}  // namespace

Command makeEvalCommand() {
  return {"eval", "ATE/RPE of a trajectory against ground truth (TUM format); eval loops: loop detection P-R; eval masks: late masks P-R", runEval};
}

}  // namespace plslam::cli
