#include "dense/dense_products.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "core/log.h"

namespace plslam {

namespace {

const Logger kLog("dense");

// A field of /proc/self/status in kB, as MB (0 when absent).
double procStatusMb(const char* field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field, 0) == 0) return std::atof(line.c_str() + std::strlen(field)) / 1024.0;
  return 0;
}

template <typename F>
void timed(DenseProducts* p, const std::string& step, F f) {
  resetPeakResident();
  DenseCost c;
  c.step = step;
  c.start_rss_mb = residentMb();
  const auto t0 = std::chrono::steady_clock::now();
  f();
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  c.peak_rss_mb = peakResidentMb();
  p->costs.push_back(c);
  kLog.info(str(step, ": ", c.seconds, " s, peak RSS ", c.peak_rss_mb, " MB"));
}

std::string fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

double residentMb() { return procStatusMb("VmRSS:"); }
double peakResidentMb() { return procStatusMb("VmHWM:"); }
bool resetPeakResident() {
  std::ofstream out("/proc/self/clear_refs");
  if (!out) return false;
  out << "5";  // "5": reset the peak resident set size (Linux >= 4.0)
  out.flush();
  return static_cast<bool>(out);
}

void validateDenseOptions(const DenseOptions& o) {
  const auto need = [](bool ok, const char* key, const std::string& why) {
    if (!ok) throw ConfigError(std::string("dense.") + key + ": " + why);
  };
  need(o.min_depth_m >= 0 && o.max_depth_m > o.min_depth_m, "max_depth_m", "must exceed min_depth_m >= 0");
  need(o.pixel_stride >= 1, "pixel_stride", "must be >= 1");
  need(o.edge_jump_ratio >= 0, "edge_jump_ratio", "must be >= 0");
  need(o.smooth_radius_px >= 0 && o.smooth_radius_px <= 10, "smooth_radius_px", "must be in [0, 10]");
  need(o.depth_sigma_coeff >= 0, "depth_sigma_coeff", "must be >= 0");
  need(o.keyframe_voxel_m >= 0, "keyframe_voxel_m", "must be >= 0");
  need(o.fused_voxel_m >= 0, "fused_voxel_m", "must be >= 0");
  need(o.min_voxel_points >= 1, "min_voxel_points", "must be >= 1");
  need(o.octree_resolution_m >= 0.001 && o.octree_resolution_m <= 10, "octree_resolution_m", "must be in [0.001, 10]");
  need(o.prob_hit > 0.5 && o.prob_hit < 1, "prob_hit", "must be in (0.5, 1)");
  need(o.prob_miss > 0 && o.prob_miss < 0.5, "prob_miss", "must be in (0, 0.5)");
  need(o.occupied_thresh > 0 && o.occupied_thresh < 1, "occupied_thresh", "must be in (0, 1)");
  need(o.floor == "ransac" || o.floor == "gravity", "floor", "must be ransac or gravity, not '" + o.floor + "'");
  need(o.floor_max_tilt_deg > 0 && o.floor_max_tilt_deg < 90, "floor_max_tilt_deg", "must be in (0, 90)");
  need(o.floor_inlier_m > 0, "floor_inlier_m", "must be > 0");
  need(o.floor_min_fraction > 0 && o.floor_min_fraction < 1, "floor_min_fraction", "must be in (0, 1)");
  need(o.floor_max_above_base_m >= 0, "floor_max_above_base_m", "must be >= 0");
  need(o.floor_search_fraction > 0 && o.floor_search_fraction <= 1, "floor_search_fraction", "must be in (0, 1]");
  need(o.grid_max_height_m > o.grid_min_height_m, "grid_max_height_m", "must exceed grid_min_height_m");
  need(o.grid_resolution_m >= 0.005 && o.grid_resolution_m <= 10, "grid_resolution_m", "must be in [0.005, 10]");
  // map_server reads a pixel p of grid.pgm as occupancy (255 - p) / 255: the free cells (254)
  // as 1/255, the unknown ones (205) as 50/255, the occupied ones (0) as 1. Thresholds on the
  // wrong side of those turn unknown space into free (or occupied) space for the planner.
  need(o.grid_free_thresh > 1.0 / 255 && o.grid_free_thresh < 50.0 / 255, "grid_free_thresh",
       "must be in (1/255, 50/255) = (0.0039, 0.1961): map_server reads free cells as 1/255 and unknown cells as "
       "50/255, so from 50/255 up unknown space reads as free");
  need(o.grid_occupied_thresh > 50.0 / 255 && o.grid_occupied_thresh < 1, "grid_occupied_thresh",
       "must be in (50/255, 1) = (0.1961, 1): map_server reads unknown cells as 50/255 and occupied cells as 1");
  need(o.live_every_keyframes >= 0, "live_every_keyframes", "must be >= 0 (0: not by count)");
  need(o.live_every_s >= 0, "live_every_s", "must be >= 0 (0: not by time)");
  need(o.live_nice >= 0 && o.live_nice <= 19, "live_nice", "must be in 0..19");
}

DenseProducts buildDenseProducts(const Map& map, const PinholeCamera& camera, const DenseOptions& o,
                                 const DenseSelection& what, const DenseProgress& progress, const MapFrame* given) {
  validateDenseOptions(o);
  DenseProducts p;
  p.keyframes = static_cast<int>(map.keyframes().size());
  for (const auto& [id, kf] : map.keyframes()) {
    p.keyframes_with_cloud += !kf.dense.empty();
    p.keyframe_points += kf.dense.size();
  }
  if (!what.any()) return p;
  // The floor is found in the fused world cloud, so the cloud is needed unless the frame is given.
  const bool need_cloud = what.pcd || what.ply || what.semantic_octomap || what.grid || !given;
  const bool need_octree = what.octomap || what.semantic_octomap || what.grid;

  bool stop = false;
  if (need_cloud) timed(&p, "cloud", [&] { p.cloud = fuseCloud(map, o, progress, &stop); });
  if (!stop) timed(&p, "map frame", [&] {
    p.frame = given ? *given : estimateMapFrame(map, camera, p.cloud, o, &p.floor);
    for (FusedPoint& q : p.cloud) q.p_w = (p.frame.T_map_world * q.p_w.cast<double>()).cast<float>();
  });
  if (!stop && need_octree)
    timed(&p, "octomap", [&] { p.octree = buildOctree(map, o, progress, &stop, p.frame.T_map_world); });
  if (!stop && what.semantic_octomap)
    timed(&p, "semantic octomap", [&] {
      SemanticOctrees trees = buildSemanticOctrees(*p.octree, p.cloud, o);
      p.semantic_octree = std::move(trees.colour);
      p.label_octree = std::move(trees.labels);
    });
  if (!stop && what.semantic_octomap && progress && !progress("semantic octomap", 1, 1)) stop = true;
  if (!stop && what.grid) {
    // The tree is in the map frame, which is the grid's floor frame.
    timed(&p, "grid", [&] { p.grid = projectToGrid(*p.octree, SE3(), p.frame.T_map_world.inverse(), o); });
    if (progress && !progress("grid", 1, 1)) stop = true;
  }
  p.cancelled = stop;
  return p;
}

namespace {

Json vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// A pose as its translation and quaternion (x, y, z, w).
Json poseJson(const SE3& T) {
  const Eigen::Quaterniond& q = T.quaternion();
  return {{"t", vec3(T.translation())}, {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

Json octreeJson(const octomap::OcTree& tree, const DenseOptions& o) {
  const OctreeSummary t = summarizeOctree(tree);
  return {{"resolution_m", o.octree_resolution_m},
          {"occupied_leaves", t.occupied_leaves},
          {"free_leaves", t.free_leaves},
          {"memory_bytes", t.memory_bytes}};
}

Json mapFrameJson(const DenseProducts& p) {
  return {{"T_map_world", poseJson(p.frame.T_map_world)},
          {"camera_height_m", p.frame.cameraHeight()},
          {"floor_method", p.frame.floor_method},
          {"floor_source", p.frame.floor_source},
          {"given", p.floor.method.empty()}};
}

Json gridJson(const OccupancyGrid& g, const DenseOptions& o) {
  return {{"width", g.width},
          {"height", g.height},
          {"resolution_m", g.resolution},
          {"origin", {g.origin.x(), g.origin.y(), 0}},
          {"min_height_m", o.grid_min_height_m},
          {"max_height_m", o.grid_max_height_m},
          {"occupied", g.count(OccupancyGrid::kOccupied)},
          {"free", g.count(OccupancyGrid::kFree)},
          {"unknown", g.count(OccupancyGrid::kUnknown)},
          {"T_w_grid", poseJson(g.T_w_grid)}};
}

}  // namespace

std::string denseSummaryJson(const DenseProducts& p, const DenseOptions& o, const std::vector<WrittenFile>& files) {
  Json j = {{"keyframes", p.keyframes},
            {"keyframes_with_cloud", p.keyframes_with_cloud},
            {"keyframe_points", p.keyframe_points},
            {"fused_points", p.cloud.size()},
            {"fused_voxel_m", o.fused_voxel_m},
            {"cancelled", p.cancelled}};
  if (p.octree) j["octree"] = octreeJson(*p.octree, o);
  if (!p.frame.floor_method.empty()) j["map_frame"] = mapFrameJson(p);
  if (!p.floor.method.empty())
    j["floor"] = {{"method", p.floor.method}, {"up_w", vec3(p.floor.up_w)}, {"height0_m", p.floor.height0},
                  {"inliers", p.floor.inliers}};
  if (p.grid.width > 0) j["grid"] = gridJson(p.grid, o);
  j["costs"] = Json::array();
  for (const auto& c : p.costs)
    j["costs"].push_back({{"step", c.step}, {"seconds", c.seconds}, {"peak_rss_mb", c.peak_rss_mb}, {"start_rss_mb", c.start_rss_mb}});
  j["files"] = Json::array();
  for (const WrittenFile& f : files)
    j["files"].push_back({{"name", std::filesystem::path(f.path).filename().string()}, {"bytes", f.bytes}});
  return jsonText(j);
}

std::vector<WrittenFile> writeDenseProducts(const std::string& dir, const DenseProducts& p, const DenseSelection& what,
                                            const DenseOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create the output folder " + dir + ": " + ec.message());
  std::vector<WrittenFile> files;
  const auto put = [&](const char* name, const std::string& bytes) {
    const std::string path = (fs::path(dir) / name).string();
    writeFileAtomically(path, bytes);
    files.push_back({path, bytes.size()});
  };
  if (!p.cancelled) {
    if (what.any()) put(kMapFrameYaml, mapFrameToYaml(p.frame));
    if (what.pcd) put(kDenseCloudPcd, cloudToPcd(p.cloud));
    if (what.ply) put(kDenseCloudPly, cloudToSemanticPly(p.cloud));
    if (what.octomap && p.octree) put(kOctomapBt, octreeToBt(*p.octree));
    if (what.semantic_octomap && p.semantic_octree) put(kOctomapSemanticOt, octreeToOt(*p.semantic_octree));
    if (what.semantic_octomap && p.label_octree) put(kOctomapLabelsOt, octreeToOt(*p.label_octree));
    if (what.grid && p.grid.width > 0) {
      put(kGridPgm, gridToPgm(p.grid));
      const std::string floor = "grid frame = map frame (map_frame.yaml), floor: " + p.frame.floor_method +
                                " on the " + p.frame.floor_source + " points; band " + fmt(o.grid_min_height_m) +
                                " to " + fmt(o.grid_max_height_m) + " m above it";
      put(kGridYaml, gridToYaml(p.grid, kGridPgm, o.grid_occupied_thresh, o.grid_free_thresh, floor));
    } else if (what.grid) {
      kLog.warn("no grid written: no voxel of the map lies in the height band above the floor");
    }
  }
  put(kDenseSummaryJson, denseSummaryJson(p, o, files));
  return files;
}

}  // namespace plslam
