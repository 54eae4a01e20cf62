// Where a frame's tracking time goes: wall time per front-end stage, kept per frame by the
// System and summarised in stats.json ("stages_ms") and in `plslam bench`'s profile table.
//
// Points and lines are extracted on two threads, so their stages overlap in time: the stages
// add up to more than the tracking time when the extraction runs in parallel.
//
// Thread safety: a StageTimes is a plain value; one thread writes one instance.
#pragma once

#include <array>
#include <chrono>

namespace plslam {

enum class Stage {
  kOrbDetect,    ///< ORB pyramid, FAST, quadtree distribution, orientation
  kOrbDescribe,  ///< rBRIEF descriptors
  kLsd,          ///< LSD segment detection
  kLineMerge,    ///< merging fragments, mask clipping, length filter
  kLbd,          ///< LBD descriptors of the kept segments
  kUndistort,    ///< ideal pixels and depth lookup for keypoints and segments
  kDynamic,      ///< dynamic check: adjacent-frame matching, motion, Delaunay graph, masks
  kSearch,       ///< projection search of the local map (both passes)
  kPoseOptimisation,  ///< pose-only optimisation (both passes)
  kKeyframe,     ///< keyframe decision and insertion
};
constexpr int kStageCount = 10;

/// snake_case name of a stage, as in stats.json ("orb_detect", ...).
const char* stageName(Stage stage);

/// Milliseconds per stage for one frame (0 when a stage did not run).
struct StageTimes {
  std::array<double, kStageCount> ms{};
  double& operator[](Stage s) { return ms[static_cast<int>(s)]; }
  double operator[](Stage s) const { return ms[static_cast<int>(s)]; }
  /// Adds `other`'s times to these.
  void add(const StageTimes& other) {
    for (int i = 0; i < kStageCount; ++i) ms[i] += other.ms[i];
  }
};

/// Milliseconds of wall time since `t0`.
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Adds the wall time from construction to destruction to (*times)[stage]; does nothing
/// when `times` is null.
class StageTimer {
 public:
  StageTimer(StageTimes* times, Stage stage) : times_(times), stage_(stage), t0_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    if (times_) (*times_)[stage_] += msSince(t0_);
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StageTimes* times_;
  Stage stage_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace plslam
