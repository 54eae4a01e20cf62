#include "system/run_outputs.h"

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "dense/floor_plane.h"
#include "io/trajectory_file.h"
#include "mapfile/map_file.h"

namespace plslam {

Summary summarize(std::vector<double> v) {
  Summary s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
  s.p95 = v[std::min(v.size() - 1, static_cast<size_t>(std::ceil(0.95 * v.size())) - 1)];
  s.max = v.back();
  return s;
}

namespace {

Json summaryJson(const std::vector<double>& v) {
  const Summary s = summarize(v);
  return {{"median", s.median}, {"mean", s.mean}, {"p95", s.p95}, {"max", s.max}};
}

double fraction(int part, int whole) { return whole ? static_cast<double>(part) / whole : 0.0; }

Json stagesJson(const RunStats& s) {
  Json out = Json::object();
  for (int i = 0; i < kStageCount; ++i) out[stageName(static_cast<Stage>(i))] = summaryJson(s.stage_ms[i]);
  return out;
}

Json trackingMethodsJson(const RunStats& s) {
  Json out = Json::object();
  for (int i = 0; i < kTrackingMethodCount; ++i) out[toString(static_cast<TrackingMethod>(i))] = s.methods[i];
  return out;
}

Json dynamicJson(const RunStats& s) {
  return {{"segmenter", s.segmenter},
          {"points_rejected_per_frame", summaryJson(s.dynamic_points_rejected)},
          {"segmentation_ms", summaryJson(s.segmentation_ms)},
          {"segmentations", s.segmentation_ms.size()},
          {"fresh_mask_fraction", fraction(s.fresh_segmentations, s.frames)},
          {"mask_age_frames", summaryJson(s.mask_age_frames)}};
}

Json loopJson(const RunStats& s) {
  Json refused = Json::object();
  for (int i = 1; i < kLoopStatusCount; ++i) refused[toString(static_cast<LoopStatus>(i))] = s.loop.refused[i];
  return {{"keyframes", s.loop.queries},
          {"candidates", s.loop.candidates},
          {"accepted", s.loop.accepted},
          {"refused", refused},
          {"correction_ms", summaryJson(s.loop.correction_ms)},
          {"correction_hold_ms", summaryJson(s.loop.correction_hold_ms)}};
}

}  // namespace

Json statsJson(const RunStats& s, const Json& extra) {
  if (!extra.is_null() && !extra.is_object()) throw std::invalid_argument("statsJson: `extra` must be a JSON object");
  Json j = {{"frames", s.frames},
            {"tracked", s.tracked},
            {"tracked_fraction", fraction(s.tracked, s.frames)},
            {"keyframes", s.keyframes},
            {"lost_events", s.lost_events},
            {"relocalisations", s.relocalisations},
            {"reanchors", s.reanchors},
            {"refined_frames", s.refined_frames},
            {"map_points", s.map_points},
            {"map_lines", s.map_lines},
            {"tracking_ms", summaryJson(s.tracking_ms)},
            {"features_ms", summaryJson(s.features_ms)},
            {"local_ba_ms", summaryJson(s.ba_ms)},
            {"refinement_ms", summaryJson(s.refinement_ms)},
            {"stages_ms", stagesJson(s)},
            {"tracking_methods", trackingMethodsJson(s)},
            {"recovery",
             {{"events", s.recovery_frames.size()},
              {"lost_frames", summaryJson(s.recovery_frames)},
              {"seconds", summaryJson(s.recovery_s)}}},
            {"line_reconstruction_rate",
             {{"fitting", s.line_rate_fitting}, {"endpoints", s.line_rate_endpoints}, {"keyframes", s.line_rate_keyframes}}},
            {"dynamic", dynamicJson(s)},
            {"modules",
             {{"lines", s.use_lines}, {"dynamic", s.use_dynamic}, {"loop_closure", s.use_loop}, {"sequential", s.sequential}}}};
  if (s.use_loop) j["loop"] = loopJson(s);
  if (extra.is_object()) j.update(extra);
  return j;
}

std::string statsToJson(const RunStats& stats, const Json& extra) { return jsonText(statsJson(stats, extra)); }

std::string framesToCsv(const std::vector<FrameRecord>& records) {
  std::ostringstream os;
  os << "t_s,status,tracking_ms,features_ms";
  for (int i = 0; i < kStageCount; ++i) os << "," << stageName(static_cast<Stage>(i)) << "_ms";
  os << ",refinement_ms,segmentation_ms,mask_age_frames,keyframes_before,points,lines,matched_points,matched_lines,"
        "dynamic_points_rejected,method,local_points,local_lines\n";
  char buf[64];
  auto number = [&](double x) {
    std::snprintf(buf, sizeof(buf), "%.3f", x);
    return std::string(buf);
  };
  for (const FrameRecord& r : records) {
    std::snprintf(buf, sizeof(buf), "%.6f", nsToSeconds(r.t_ns));
    os << buf << "," << toString(r.status) << "," << number(r.tracking_ms) << "," << number(r.features_ms);
    for (int i = 0; i < kStageCount; ++i) os << "," << number(r.stages.ms[i]);
    os << "," << number(r.refinement_ms) << "," << (r.segmentation_ms >= 0 ? number(r.segmentation_ms) : "")
       << "," << r.mask_age_frames << "," << r.keyframes_before << "," << r.points << "," << r.lines << ","
       << r.matched_points << "," << r.matched_lines << "," << r.dynamic_points_rejected << "," << toString(r.method)
       << "," << r.local_points << "," << r.local_lines << "\n";
  }
  return os.str();
}

std::string sparseMapToPly(const Map& map, const SE3& T_out_w) {
  std::lock_guard<std::mutex> lock(map.mutex());
  const size_t np = map.points().size(), nl = map.lines().size();
  std::ostringstream os;
  os << "ply\nformat ascii 1.0\ncomment plslam sparse map: points (grey), 3D line endpoints (red), lines as edges\n"
     << "element vertex " << np + 2 * nl << "\nproperty float x\nproperty float y\nproperty float z\n"
     << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
     << "element edge " << nl << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  char buf[128];
  for (const auto& [id, p] : map.points()) {
    const Eigen::Vector3d q = T_out_w * p.p_w;
    std::snprintf(buf, sizeof(buf), "%.5f %.5f %.5f 160 160 160\n", q.x(), q.y(), q.z());
    os << buf;
  }
  for (const auto& [id, l] : map.lines()) {
    for (const Eigen::Vector3d& e : {Eigen::Vector3d(T_out_w * l.P_w), Eigen::Vector3d(T_out_w * l.Q_w)}) {
      std::snprintf(buf, sizeof(buf), "%.5f %.5f %.5f 230 40 40\n", e.x(), e.y(), e.z());
      os << buf;
    }
  }
  for (size_t i = 0; i < nl; ++i) os << np + 2 * i << " " << np + 2 * i + 1 << "\n";
  return os.str();
}

Trajectory baseTrajectory(const Trajectory& trajectory, const SE3& T_map_world, const SE3& T_base_cam) {
  const SE3 T_cam_base = T_base_cam.inverse();
  Trajectory out = trajectory;
  for (StampedPose& p : out) p.T_w_c = T_map_world * p.T_w_c * T_cam_base;
  return out;
}

MapFrame sparseMapFrame(const System& system) {
  std::lock_guard<std::mutex> lock(system.map().mutex());
  return estimateMapFrame(system.map(), system.camera(), {}, system.options().dense);
}

void writeRunOutputs(const std::string& dir, const System& system, const std::string& config_yaml,
                     const Json& stats_extra, const std::string& map_path, const MapFrame* frame) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir)) throw IoError(dir + ": cannot create the output folder");
  const MapFrame map_frame = frame ? *frame : sparseMapFrame(system);
  const Trajectory trajectory = system.trajectory();
  Trajectory in_map = trajectory;
  for (StampedPose& p : in_map) p.T_w_c = map_frame.T_map_world * p.T_w_c;
  writeTumTrajectory(dir + "/trajectory.txt", trajectory, "plslam trajectory: every tracked frame, T_w_c");
  writeTumTrajectory(dir + "/" + kTrajectoryMap, in_map,
                     "plslam trajectory in the map frame (map_frame.yaml): every tracked frame, T_map_c");
  if (const auto& T_base_cam = system.options().dense.T_base_cam)
    writeTumTrajectory(dir + "/" + kTrajectoryBase, baseTrajectory(trajectory, map_frame.T_map_world, *T_base_cam),
                       "plslam base trajectory in the map frame (map_frame.yaml): every tracked frame, T_map_base");
  writeTumTrajectory(dir + "/keyframes.txt", system.keyframeTrajectory(), "plslam keyframes, T_w_c");
  writeFileAtomically(dir + "/" + kMapFrameYaml, mapFrameToYaml(map_frame));
  writeFileAtomically(dir + "/sparse_map.ply", sparseMapToPly(system.map(), map_frame.T_map_world));
  writeFileAtomically(dir + "/stats.json", statsToJson(system.stats(), stats_extra));
  writeFileAtomically(dir + "/frames.csv", framesToCsv(system.records()));
  if (!config_yaml.empty()) writeFileAtomically(dir + "/config.yaml", config_yaml);
  saveMap(map_path.empty() ? dir + "/" + kDefaultMapFileName : map_path, system.map(), system.camera(), config_yaml,
          &map_frame);
}

}  // namespace plslam
