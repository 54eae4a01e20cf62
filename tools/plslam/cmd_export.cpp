// plslam export: the dense products (fused cloud, OctoMaps, 2D grid) of a saved map.
#include <cstdio>
#include <map>

#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"
#include "dense_cli.h"
#include "mapfile/map_file.h"
#include "run_session.h"
#include "system/system.h"

namespace plslam::cli {

namespace {
const Logger kLog("export");

int runExport(int argc, char** argv) {
  Args args("export", "Dense maps of a saved map: fused cloud (PCD, PLY), OctoMaps (.bt, .ot) and a 2D occupancy grid.");
  args.option("map", "the saved map (a run's map.plmap)", "", true)
      .option("out", "output folder (created if needed)", "", true)
      .flag("pcd", "dense_cloud.pcd: fused cloud, PointXYZRGBL (label = class + 1)")
      .flag("ply", "dense_cloud_semantic.ply: fused cloud with semantic colours and classes")
      .flag("octomap", "octomap.bt (occupancy), octomap_semantic.ot (semantic colours) and octomap_labels.ot (class ids)")
      .flag("grid", "grid.pgm + grid.yaml: 2D occupancy grid (ROS map_server)")
      .option("config", "YAML with dense.* keys (default: the map's own configuration)")
      .option("voxel", "fused cloud voxel size (m)")
      .option("resolution", "OctoMap leaf size (m)")
      .option("max-range", "OctoMap ray range (m)")
      .option("grid-resolution", "grid cell size (m; default: the OctoMap resolution)")
      .option("grid-min-height", "lower end of the obstacle band above the floor (m)")
      .option("grid-max-height", "upper end of the obstacle band above the floor (m)")
      .option("floor", "ransac (lowest level plane) or gravity (the first camera's image up)")
      .option("log-level", "debug, info, warn, error or off", "warn")
      .flag("quiet", "no progress line")
      .epilog(
          "All products when none of --pcd --ply --octomap --grid is given. Each file is written atomically;\n"
          "Ctrl-C stops without leaving a partial product. dense_products.json lists counts, the floor,\n"
          "time and peak memory per step, and the file sizes. Every product is in the map frame stored in\n"
          "the map (map_frame.yaml; for an older map without one it is found from the floor as run does).\n\n"
          "example: plslam export --map maps/fr1_xyz/map.plmap --out maps/fr1_xyz/dense --voxel 0.01 --resolution 0.05");
  if (!args.parse(argc, argv)) return 0;
  setLogLevel(parseLogLevel(args.str("log-level")));

  const LoadedMap loaded = loadMap(args.str("map"));
  // The dense options: the map's run configuration (its dense.* keys), then --config, then flags.
  SystemOptions options;
  OptionTable table;
  bindOptions(&table, &options);
  // Other sections are the run's business and are skipped. An unknown dense.* key in the
  // user's --config is refused (a misspelt key would otherwise do nothing, silently); in the
  // map's own configuration it is a key of the version that wrote the map, and is skipped
  // with a warning.
  const auto applyDense = [&](const std::map<std::string, std::string>& values, const std::string& source,
                              bool refuse_unknown) {
    for (const auto& [key, value] : values) {
      if (key.rfind("dense.", 0) != 0) continue;
      if (table.has(key) || refuse_unknown) table.set(key, value, source);
      else kLog.warn(source + ": option '" + key + "' is not known to this version; skipped");
    }
  };
  if (!loaded.config_yaml.empty())
    applyDense(parseYamlSubset(loaded.config_yaml, args.str("map")), args.str("map"), false);
  if (args.has("config")) {
    const std::string path = args.str("config");
    applyDense(parseYamlSubset(readTextFile(path), path), path, true);
  }
  DenseOptions& o = options.dense;
  if (args.has("voxel")) o.fused_voxel_m = args.number("voxel");
  if (args.has("resolution")) {
    o.octree_resolution_m = args.number("resolution");
    if (!args.has("grid-resolution")) o.grid_resolution_m = o.octree_resolution_m;
  }
  if (args.has("grid-resolution")) o.grid_resolution_m = args.number("grid-resolution");
  if (args.has("max-range")) o.max_range_m = args.number("max-range");
  if (args.has("grid-min-height")) o.grid_min_height_m = args.number("grid-min-height");
  if (args.has("grid-max-height")) o.grid_max_height_m = args.number("grid-max-height");
  if (args.has("floor")) o.floor = args.str("floor");
  validateDenseOptions(o);

  DenseSelection what;
  if (args.has("pcd") || args.has("ply") || args.has("octomap") || args.has("grid")) {
    what.pcd = args.has("pcd");
    what.ply = args.has("ply");
    what.octomap = what.semantic_octomap = args.has("octomap");
    what.grid = args.has("grid");
  }
  size_t with_cloud = 0;
  for (const auto& [id, kf] : loaded.map.keyframes()) with_cloud += !kf.dense.empty();
  if (with_cloud == 0)
    throw DataError(args.str("map") + ": none of its " + std::to_string(loaded.map.keyframes().size()) +
                    " keyframes has a dense cloud (was it made with dense.enabled: false?)");
  // The map frame stored with the map (the run's outputs are in it); older maps: found anew.
  return writeDenseMaps(loaded.map, loaded.camera, o, what, args.str("out"), !args.has("quiet"),
                        loaded.frame ? &*loaded.frame : nullptr)
             ? 0
             : 130;
}

}  // namespace

Command makeExportCommand() { return {"export", "dense maps of a saved map: PCD/PLY cloud, OctoMap, 2D grid", runExport}; }

}  // namespace plslam::cli
