// Times the optimisers on synthetic problems: bench_optim [repetitions]
// Prints median / min / max wall times (ms). Build Release; the machine may be noisy.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "optim/bundle_adjuster.h"
#include "optim/pose_graph.h"
#include "optim/pose_optimizer.h"
#include "synthetic_scene.h"

using namespace plslam;
using namespace plslam::test;

namespace {

void report(const char* what, std::vector<double> ms, const char* extra = "") {
  std::sort(ms.begin(), ms.end());
  std::printf("%-58s median %8.2f ms  min %8.2f  max %8.2f  (n=%zu) %s\n", what, ms[ms.size() / 2], ms.front(), ms.back(),
              ms.size(), extra);
}

void benchPoseOnly(int reps, bool normal_cholesky, const char* label) {
  const PinholeCamera cam = syntheticCamera();
  std::mt19937 rng(100);
  PoseOptimizerOptions options;
  options.normal_cholesky = normal_cholesky;
  const PoseOptimizer optimizer(options);
  std::vector<double> ms;
  double worst_t = 0;
  for (int i = 0; i < reps; ++i) {
    PoseOnlyScene s = makePoseOnlyScene(cam, 500, 100, true, 0.5, 1.0, rng);
    s.problem.T_w_c_init = perturb(s.T_w_c_true, 0.05, 3.0, rng);
    const PoseOnlyResult r = optimizer.optimize(cam, s.problem);
    if (!r.converged) std::printf("  run %d: %s\n", i, toString(r.status));
    worst_t = std::max(worst_t, (r.T_w_c.translation() - s.T_w_c_true.translation()).norm());
    ms.push_back(r.time_ms);
  }
  char extra[64];
  std::snprintf(extra, sizeof extra, "worst error %.2f mm", 1e3 * worst_t);
  report(label, ms, extra);
}

void benchBundle(int reps, int n_kf, int n_points, int n_lines, int views, const char* label) {
  const PinholeCamera cam = syntheticCamera();
  std::mt19937 rng(200);
  std::vector<double> ms;
  int iterations = 0;
  size_t obs = 0;
  for (int i = 0; i < reps; ++i) {
    BundleScene s = makeBundleScene(cam, n_kf, n_points, n_lines, true, 0.5, rng, views);
    s.problem.keyframes[0].fixed = true;
    for (auto& kf : s.problem.keyframes)
      if (!kf.fixed) kf.T_w_c = perturb(kf.T_w_c, 0.01, 0.5, rng);
    for (auto& p : s.problem.points) p.p_w += 0.02 * randomUnit(rng);
    for (auto& l : s.problem.lines) l.P_w += 0.02 * randomUnit(rng), l.Q_w += 0.02 * randomUnit(rng);
    BundleAdjusterOptions options;  // defaults: 10 + 10 iterations, dense Schur, 1 thread
    const BundleResult r = BundleAdjuster(options).adjust(cam, s.problem);
    if (!r.ok()) std::printf("  run %d: %s\n", i, toString(r.status));
    ms.push_back(r.time_ms);
    iterations = r.iterations;
    obs = s.problem.point_obs.size() + s.problem.line_obs.size();
  }
  char extra[96];
  std::snprintf(extra, sizeof extra, "%zu observations, %d iterations", obs, iterations);
  report(label, ms, extra);
}

}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 50;
  benchPoseOnly(reps, true, "pose-only 500 pts (depth) + 100 lines, normal Cholesky");
  benchPoseOnly(reps, false, "pose-only 500 pts (depth) + 100 lines, dense QR");
  const int ba_reps = std::max(1, reps / 10);
  benchBundle(ba_reps, 10, 3000, 0, 5, "local BA 10 kf, 3000 pts x 5 views");
  benchBundle(ba_reps, 10, 3000, 200, 5, "local BA 10 kf, 3000 pts x 5 views + 200 lines x 10");
  benchBundle(ba_reps, 10, 3000, 200, 0, "local BA 10 kf, 3000 pts x 10 views + 200 lines x 10");
  return 0;
}
