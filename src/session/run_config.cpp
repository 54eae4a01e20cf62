#include "session/run_config.h"

#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "calibration/base_transform.h"
#include "core/error.h"

namespace plslam {

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open configuration file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

namespace {

// The robot's mounting, read once here for every front end: the map frame (dense/floor_plane.h)
// and trajectory_base.txt (system/run_outputs.h) take it from the options.
void loadCalibration(SystemOptions* options) {
  options->dense.T_base_cam.reset();
  if (!options->camera_to_base.empty()) options->dense.T_base_cam = calib::loadCameraToBase(options->camera_to_base);
  validateDepthCorrection(options->depth_correction);
}

}  // namespace

void loadRunConfig(const std::string& config_path, SystemOptions* options, OptionTable* table) {
  bindOptions(table, options);
  if (!config_path.empty()) table->apply(parseYamlSubset(readTextFile(config_path), config_path), config_path);
  loadCalibration(options);  // plslam bench and eval masks have no other switches
}

namespace {

// The segmenter, dynamic classes and feature switches, over whatever the files said.
void applySwitches(const RunSwitches& s, SystemOptions* options) {
  if (s.sequential) options->sequential = true;
  if (s.no_lines) options->use_lines = false;
  if (s.no_dynamic) options->dynamic.enabled = false;
  if (s.no_loop) options->use_loop = false;
  SegmenterOptions& seg = options->segmenter;
  if (s.segmenter == "none" || s.segmenter == "replay" || s.segmenter == "yolo") {
    seg.kind = parseSegmenterKind(s.segmenter);
  } else if (!s.segmenter.empty()) {
    seg.kind = SegmenterKind::kYolo;
    seg.yolo.model_path = s.segmenter;
  }
  if (!s.classes.empty()) seg.classes_file = s.classes;
  if (!splitCommaList(s.dynamic_classes).empty()) seg.dynamic_classes = splitCommaList(s.dynamic_classes);
  if (s.allow_missing_model) seg.allow_missing_model = true;
  if (!s.base.empty()) options->camera_to_base = s.base;
}

// A saved map's configuration without its segmenter.* keys: which segmenter runs (a replay
// of a folder's masks, a model file of another machine) is the session's choice.
std::map<std::string, std::string> withoutSegmenter(std::map<std::string, std::string> values) {
  for (auto it = values.begin(); it != values.end();)
    it = it->first.rfind("segmenter.", 0) == 0 ? values.erase(it) : std::next(it);
  return values;
}

}  // namespace

RunConfig makeRunConfig(const RunSwitches& switches, const std::string& title) {
  if (switches.localize && switches.map.empty()) throw ConfigError("--localize needs --map FILE");
  RunConfig config;
  OptionTable table;
  if (!switches.map.empty()) {
    // The map's own configuration first (same features and tracking), then the file over it.
    config.map = loadMap(switches.map);
    bindOptions(&table, &config.options);
    if (!config.map->config_yaml.empty())
      table.apply(withoutSegmenter(parseYamlSubset(config.map->config_yaml, switches.map)),
                  switches.map + " (saved configuration)");
    if (!switches.config.empty())
      table.apply(parseYamlSubset(readTextFile(switches.config), switches.config), switches.config);
    config.options.tracker.localization_only = switches.localize;
  } else {
    loadRunConfig(switches.config, &config.options, &table);
  }
  applySwitches(switches, &config.options);
  loadCalibration(&config.options);
  config.config_yaml = table.toYaml(title);
  return config;
}

}  // namespace plslam
