// The configuration of a SLAM session from the switches every front end offers
// (`plslam run`, the ROS node, and any later adapter): a YAML file, a saved map whose own
// configuration is the base, and the command-line style overrides. One place, so that
// `plslam run --no-loop` and the node's `no_loop` parameter cannot drift apart.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/option_table.h"
#include "mapfile/map_file.h"
#include "system/system.h"

namespace plslam {

/// The whole content of a text file; IoError naming it when it cannot be read.
std::string readTextFile(const std::string& path);

/// Binds `options` into `table` and applies the YAML file `config_path` (none when empty),
/// then loads calibration.camera_to_base into options->dense.T_base_cam.
void loadRunConfig(const std::string& config_path, SystemOptions* options, OptionTable* table);

/// The switches of `plslam run` that shape the System (the same names, as the node's parameters).
struct RunSwitches {
  std::string config;              ///< YAML run options (empty: defaults)
  std::string map;                 ///< start from this saved map (.plmap); its configuration is the base
  bool localize = false;           ///< with map: track without changing it
  bool sequential = false;         ///< deterministic single-thread System
  bool no_lines = false;           ///< points only
  bool no_dynamic = false;         ///< no rejection of moving objects
  bool no_loop = false;            ///< no loop closure
  // The segmenter switches override the segmenter.* keys of the files; empty / false: not given.
  std::string segmenter;           ///< none, replay, yolo (model: segmenter.model) or a YOLOv8-seg .onnx file
  std::string classes;             ///< class names file (over segmenter.classes)
  std::string dynamic_classes;     ///< comma-separated names that may move (over segmenter.dynamic_classes)
  bool allow_missing_model = false;  ///< go on with the geometric checks when the model cannot be used
  std::string base;                ///< camera-to-base file of `plslam calib base` (over calibration.camera_to_base)
};

/// What a session starts from.
struct RunConfig {
  SystemOptions options;
  std::string config_yaml;        ///< the effective configuration (written beside the outputs)
  std::optional<LoadedMap> map;   ///< the saved map, when switches.map was given
};

/// Applies `switches` in the order of `plslam run`: the map's saved configuration (but for
/// its segmenter.* keys: the segmenter belongs to the session, not to the map), then the
/// YAML file, then the switches; then loads the camera-to-base file
/// (calibration.camera_to_base) into options.dense.T_base_cam, the one place it is read. `title` heads config_yaml. Throws ConfigError for a
/// bad combination (localize without map) or key, IoError for an unreadable file.
RunConfig makeRunConfig(const RunSwitches& switches, const std::string& title);

}  // namespace plslam
