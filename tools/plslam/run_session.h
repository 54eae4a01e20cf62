// Pieces shared by `plslam run` and `plslam bench` (and `eval loops`): feeding a recorded
// folder or bag to a System (progress callback, Ctrl-C), and the evaluation of the
// resulting trajectory against its ground truth. The run configuration itself is
// session/run_config.h, shared with the ROS node.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "args.h"
#include "core/json.h"
#include "core/option_table.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "io/dataset.h"
#include "io/frame_source.h"
#include "session/run_config.h"
#include "system/system.h"

namespace plslam::cli {

/// Declares the switches that shape the System, the same for plslam run and plslam live
/// (session/run_config.h applies them): --config, --no-lines, --segmenter, --classes,
/// --dynamic-classes, --allow-missing-model, --no-dynamic, --no-loop, --map, --localize,
/// --base. Each command declares its own --sequential (what it implies differs).
void addRunSwitches(Args* args);
/// The switches of a parsed command line that declared them.
RunSwitches runSwitches(const Args& args);

/// The classes of the instance ids in `dataset`'s masks (masks.txt), for the replay segmenter.
std::vector<InstanceClass> replayLabels(const TumDataset& dataset);


/// While an instance lives, Ctrl-C sets interrupted() instead of ending the process; the
/// previous handler is restored on destruction. A guard made inside another (the dense
/// maps' within a run's) clears interrupted() and hands the outer one back its handler.
class SigintGuard {
 public:
  SigintGuard();
  ~SigintGuard();
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;
  /// Ctrl-C was pressed since the last guard was created.
  static bool interrupted();

 private:
  void (*previous_)(int) = nullptr;
};

struct FeedProgress {
  size_t done = 0;       ///< frames fed so far
  size_t total = 0;      ///< frames in the dataset
  int tracked = 0;       ///< frames tracked so far
  size_t keyframes = 0;  ///< keyframes in the map now
  double seconds = 0;    ///< since the first frame was read
};

struct FeedResult {
  size_t fed = 0;
  int tracked = 0;
  double seconds = 0;        ///< wall time of the feeding loop
  bool interrupted = false;  ///< stopped by Ctrl-C (SigintGuard)
  std::string last_failure;  ///< the tracker's reason for the last frame it could not track (empty: none)
};

/// How frames are handed to the System.
enum class Pace {
  kAsFastAsPossible,  ///< the next frame as soon as the last one is tracked (offline processing)
  kRecorded,          ///< each frame at its recorded time after the first, as a camera delivers them; a
                      ///< frame that is late is fed at once (no catching up by skipping)
};

/// Feeds every loadable frame of `source` (from its current position) to the started
/// `slam`; stops early on Ctrl-C while a SigintGuard lives. `progress` (may be empty) is
/// called at most every `period_ms` and once after the last frame.
FeedResult feedFrames(System* slam, FrameSource* source, const std::function<void(const FeedProgress&)>& progress,
                      int period_ms = 500, Pace pace = Pace::kAsFastAsPossible);

/// The comparison of a run's trajectory with the folder's ground truth.
struct RunEvaluation {
  bool attempted = false;  ///< the folder has ground truth and the estimate at least 3 poses
  bool ok = false;         ///< evaluated (result is valid)
  EvalResult result;
  std::string error;       ///< why an attempted evaluation failed

  /// JSON members for stats.json: ate_rmse_m, rpe_trans_rmse_m, rpe_rot_rmse_deg; an
  /// empty object unless ok.
  Json jsonMembers() const;
  /// One line for people: the figures, or why they are missing; empty when not attempted.
  std::string text() const;
};
/// Evaluates `estimate` against source.groundtruth() (TUM benchmark definitions).
RunEvaluation evaluateRun(const FrameSource& source, const Trajectory& estimate);

/// The extra stats.json members of a run: dataset folder or bag, skipped frames, evaluation.
Json runStatsExtra(const FrameSource& source, const RunEvaluation& evaluation);

}  // namespace plslam::cli
