// Saving and loading a SLAM map: keyframes (with every extracted feature, segmented
// instances, dense cloud and dynamic mask), map points and 3D lines with their ids and
// observations, the camera and the run configuration that built it.
//
// The file (".plmap") is versioned and self-describing (see mapfile/container.h): a text
// header says what wrote it, the counts and the section table; each section carries its
// byte length and CRC-32. Sections of format version 1, in order:
//   camera     name, image size, fx fy cx cy, k1 k2 p1 p2 k3, depth scale
//   config     the run configuration, YAML text as `plslam run` writes it (may be empty)
//   keyframes  id, t_ns, T_w_c, keypoints, segments, descriptors, point_ids, line_ids,
//              instances, dense cloud, dynamic mask (run-length coded, or absent)
//   points     id, position, descriptor, observations, first keyframe, visible / found
//   lines      id, endpoints, descriptor, observations, first keyframe, visible / found
//   map_frame  optional: T_map_world and how it was found, the text of map_frame.yaml
//              (core/map_frame.h). Added without a version bump: readers skip unknown
//              sections, and files without it load with no map frame.
// Every number is little-endian (floats as their IEEE-754 bits), every count u32.
//
// Errors: IoError for the file itself (missing, unreadable, not a map, other format
// version, truncated, CRC mismatch, malformed section), DataError for content that
// decodes but does not hold together (ids, observations, sizes, camera). Messages name the
// file and the section.
#pragma once

#include <optional>
#include <string>

#include "camera/pinhole_camera.h"
#include "core/map.h"
#include "core/map_frame.h"

namespace plslam {

/// File name `plslam run` gives the map in its output folder.
inline constexpr char kDefaultMapFileName[] = "map.plmap";

struct LoadedMap {
  PinholeCamera camera;      ///< the camera the map was built with
  std::string config_yaml;   ///< the run configuration that built it (may be empty)
  std::string writer;        ///< what wrote the file
  Map map;                   ///< entities with their saved ids; new ones get larger ids
  std::optional<MapFrame> frame;  ///< the map frame of its outputs (absent in older files)
};

/// The file's bytes. Deterministic: the same map, camera and text give the same bytes.
/// Locks map.mutex() while it reads. Throws DataError for what the format cannot hold
/// (descriptors that are not CV_8UC1, masks that are not CV_8UC1 of the camera's size).
/// `frame` (may be null) is stored as the map_frame section.
std::string serializeMap(const Map& map, const PinholeCamera& camera, const std::string& config_yaml,
                         const MapFrame* frame = nullptr);
/// serializeMap() written atomically (core/atomic_file.h): an interruption leaves the
/// previous file or none, never a partial one.
void saveMap(const std::string& path, const Map& map, const PinholeCamera& camera, const std::string& config_yaml,
             const MapFrame* frame = nullptr);

/// Reads and checks a map file (see the error list above).
LoadedMap loadMap(const std::string& path);
/// The same from the file's bytes; `name_for_messages` stands for the file in errors.
/// Safe on any byte string: it throws plslam::Error (IoError / DataError) or returns.
LoadedMap parseMap(const std::string& bytes, const std::string& name_for_messages);

}  // namespace plslam
