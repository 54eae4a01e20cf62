// What a run leaves in its output folder, each file written atomically:
//   trajectory.txt   TUM format, every tracked frame, final poses (T_w_c, SLAM world = the
//                    first keyframe's camera: the TUM convention, for evaluation)
//   trajectory_map.txt  the same camera poses in the map frame (T_map_c)
//   trajectory_base.txt with a camera-to-base transform (calibration.camera_to_base): the
//                    robot base's poses in the map frame, T_map_base = T_map_c * T_base_cam^-1
//   keyframes.txt    TUM format, keyframe poses (T_w_c)
//   map_frame.yaml   T_map_world and how it was found (core/map_frame.h)
//   sparse_map.ply   map frame, ASCII PLY: map points (grey) and 3D line endpoints (red) as vertices,
//                    each 3D line an `edge` between its two endpoints (PCL, CloudCompare,
//                    MeshLab and Open3D read the vertices; CloudCompare/MeshLab draw the edges)
//   stats.json       run figures (see RunStats)
//   config.yaml      the effective configuration
//   map.plmap        the map (keyframes, landmarks, camera, configuration, map frame) for
//                    `plslam run --map map.plmap [--localize]` (mapfile/map_file.h)
#pragma once

#include <string>

#include "core/json.h"
#include "core/map_frame.h"
#include "system/system.h"

namespace plslam {

/// Statistics as one JSON object; the members of `extra` (an object, or null) are added
/// for the caller's own fields (dataset, ATE...). Throws std::invalid_argument when `extra`
/// is anything else.
Json statsJson(const RunStats& stats, const Json& extra = nullptr);
/// statsJson as the text of stats.json.
std::string statsToJson(const RunStats& stats, const Json& extra = nullptr);
/// One CSV line per input frame (header first): time, status, tracking and feature times, the
/// time of each stage (core/profile.h), segmentation, counts. What `frames.csv` holds.
std::string framesToCsv(const std::vector<FrameRecord>& records);

/// The sparse map as ASCII PLY (points and lines, see above). Points and line endpoints
/// are moved by T_out_w (the map frame: T_map_world).
std::string sparseMapToPly(const Map& map, const SE3& T_out_w = SE3());

inline constexpr char kTrajectoryMap[] = "trajectory_map.txt";
inline constexpr char kTrajectoryBase[] = "trajectory_base.txt";

/// The camera poses T_w_c of `trajectory` as poses of the base in the map frame:
/// T_map_base = T_map_world * T_w_c * T_base_cam^-1.
Trajectory baseTrajectory(const Trajectory& trajectory, const SE3& T_map_world, const SE3& T_base_cam);

/// The map frame from the floor of the sparse map points (for runs without dense clouds).
MapFrame sparseMapFrame(const System& system);

/// Writes the files above into `dir` (created if needed; config.yaml only when
/// `config_yaml` is not empty), and the map to `map_path` (empty: dir/map.plmap), in the
/// map frame `frame` (the dense products' one), or when null sparseMapFrame(system).
/// `stats_extra` as in statsJson (an object or null: a string throws std::invalid_argument).
void writeRunOutputs(const std::string& dir, const System& system, const std::string& config_yaml,
                     const Json& stats_extra = nullptr, const std::string& map_path = "",
                     const MapFrame* frame = nullptr);

/// Median / mean / 95th percentile / maximum of `v` (0 when empty). The maximum is the
/// worst latency, where a frame waited for a loop correction.
struct Summary {
  double median = 0, mean = 0, p95 = 0, max = 0;
};
Summary summarize(std::vector<double> v);

}  // namespace plslam
