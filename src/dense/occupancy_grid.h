// A 2D occupancy grid for navigation, in the ROS map_server convention:
//   grid.pgm   binary PGM (P5), 8 bits: 0 occupied, 254 free, 205 unknown; the first row
//              is the top of the map (largest y)
//   grid.yaml  image, resolution (m/cell), origin [x, y, yaw] (the lower-left cell's corner
//              in the grid frame), negate 0, occupied_thresh, free_thresh, mode trinary;
//              comment lines give T_w_grid (the grid frame in the SLAM world frame) and the
//              floor, so a map user can place the grid on the 3D map.
// The grid frame is the floor frame of dense/floor_plane.h (z up, origin on the floor
// below the first camera).
//
// Stateless and thread-safe.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/se3.h"

namespace plslam {

struct OccupancyGrid {
  static constexpr int8_t kUnknown = -1, kFree = 0, kOccupied = 100;

  int width = 0, height = 0;           ///< cells along x and y
  double resolution = 0.05;            ///< cell size (m)
  Eigen::Vector2d origin{0, 0};        ///< grid-frame (x, y) of cell (0, 0)'s lower-left corner (m)
  SE3 T_w_grid;                        ///< grid frame in the world
  std::vector<int8_t> cells;           ///< row-major, row 0 = smallest y: kUnknown, kFree, kOccupied

  int8_t at(int x, int y) const { return cells[static_cast<size_t>(y) * width + x]; }
  int8_t& at(int x, int y) { return cells[static_cast<size_t>(y) * width + x]; }
  /// The world point above the centre of cell (x, y) at `height` over the floor.
  Eigen::Vector3d cellCentreWorld(int x, int y, double height) const;
  int count(int8_t value) const;
};

/// The grid as PGM P5 bytes (0 occupied, 254 free, 205 unknown, top row = largest y).
std::string gridToPgm(const OccupancyGrid& grid);
/// The map_server YAML naming `image_name` (relative to the YAML's folder). `comment` lines
/// (may be empty) are written as '#' comments after T_w_grid.
std::string gridToYaml(const OccupancyGrid& grid, const std::string& image_name, double occupied_thresh,
                       double free_thresh, const std::string& comment = "");

/// What a map YAML says (the keys above).
struct GridYaml {
  std::string image;
  double resolution = 0;
  Eigen::Vector3d origin{0, 0, 0};  ///< x, y, yaw
  int negate = 0;
  double occupied_thresh = 0, free_thresh = 0;
  std::string mode;
};
/// Parses a map YAML; throws IoError naming `source` when a required key is missing or
/// malformed.
GridYaml parseGridYaml(const std::string& content, const std::string& source);
/// Reads a map YAML and its PGM (trinary: thresholds applied as map_server does) back into
/// a grid (T_w_grid from the YAML's comment when present, identity otherwise). Throws
/// IoError naming the file.
OccupancyGrid readGrid(const std::string& yaml_path);

}  // namespace plslam
