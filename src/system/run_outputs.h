// What a run leaves in its output folder, each file written atomically:
//   trajectory.txt   TUM format, every tracked frame, final poses (T_w_c)
//   keyframes.txt    TUM format, keyframe poses
//   sparse_map.ply   ASCII PLY: map points (grey) and 3D line endpoints (red) as vertices,
//                    each 3D line an `edge` between its two endpoints (PCL, CloudCompare,
//                    MeshLab and Open3D read the vertices; CloudCompare/MeshLab draw the edges)
//   stats.json       run figures (see RunStats)
//   config.yaml      the effective configuration
//   map.plmap        the map (keyframes, landmarks, camera, configuration) for
//                    `plslam run --map map.plmap [--localize]` (mapfile/map_file.h)
#pragma once

#include <string>

#include "system/system.h"

namespace plslam {

/// Statistics as one JSON object. `extra` (JSON members without braces, may be empty) is
/// appended for the caller's own fields (dataset, ATE...).
std::string statsToJson(const RunStats& stats, const std::string& extra = "");
/// The sparse map as ASCII PLY (points and lines, see above).
/// One CSV line per input frame (header first): time, status, tracking and feature times, the
/// time of each stage (core/profile.h), segmentation, counts. What `frames.csv` holds.
std::string framesToCsv(const std::vector<FrameRecord>& records);

std::string sparseMapToPly(const Map& map);
/// Writes trajectory.txt, keyframes.txt, sparse_map.ply, stats.json (and config.yaml when
/// `config_yaml` is not empty) into `dir` (created if needed), and the map to `map_path`
/// (empty: dir/map.plmap).
void writeRunOutputs(const std::string& dir, const System& system, const std::string& config_yaml,
                     const std::string& stats_extra = "", const std::string& map_path = "");

/// Median / mean / 95th percentile / maximum of `v` (0 when empty). The maximum is the
/// worst latency, where a frame waited for a loop correction.
struct Summary {
  double median = 0, mean = 0, p95 = 0, max = 0;
};
Summary summarize(std::vector<double> v);

}  // namespace plslam
