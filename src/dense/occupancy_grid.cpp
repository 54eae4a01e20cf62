#include "dense/occupancy_grid.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/log.h"
#include "core/yaml.h"

namespace plslam {

namespace {

constexpr uint8_t kPgmOccupied = 0, kPgmFree = 254, kPgmUnknown = 205;

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

Eigen::Vector3d OccupancyGrid::cellCentreWorld(int x, int y, double h) const {
  return T_w_grid * Eigen::Vector3d(origin.x() + (x + 0.5) * resolution, origin.y() + (y + 0.5) * resolution, h);
}

int OccupancyGrid::count(int8_t value) const {
  int n = 0;
  for (int8_t c : cells) n += c == value;
  return n;
}

std::string gridToPgm(const OccupancyGrid& g) {
  std::string s = "P5\n# plslam occupancy grid: 0 occupied, 254 free, 205 unknown\n" + std::to_string(g.width) + " " +
                  std::to_string(g.height) + "\n255\n";
  s.reserve(s.size() + static_cast<size_t>(g.width) * g.height);
  for (int row = 0; row < g.height; ++row) {
    const int y = g.height - 1 - row;  // image top = largest y (map_server flips)
    for (int x = 0; x < g.width; ++x) {
      const int8_t c = g.at(x, y);
      s.push_back(static_cast<char>(c == OccupancyGrid::kOccupied ? kPgmOccupied
                                    : c == OccupancyGrid::kFree   ? kPgmFree
                                                                  : kPgmUnknown));
    }
  }
  return s;
}

std::string gridToYaml(const OccupancyGrid& g, const std::string& image_name, double occupied_thresh,
                       double free_thresh, const std::string& comment) {
  const Eigen::Quaterniond& q = g.T_w_grid.quaternion();
  const Eigen::Vector3d& t = g.T_w_grid.translation();
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\nnegate: 0\noccupied_thresh: %.3f\n"
                "free_thresh: %.3f\nmode: trinary\n"
                "# T_w_grid (grid frame in the SLAM world frame, tx ty tz qx qy qz qw): %.9f %.9f %.9f %.9f %.9f %.9f "
                "%.9f\n",
                image_name.c_str(), g.resolution, g.origin.x(), g.origin.y(), occupied_thresh, free_thresh, t.x(),
                t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  std::string s = buf;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) s += "# " + line + "\n";
  return s;
}

// map_server's keys; others are ignored, as map_server does.
GridYaml parseGridYaml(const std::string& content, const std::string& source) {
  const YAML::Node doc = parseYaml<IoError>(content, source);
  if (!doc.IsMap()) throw IoError(yamlAt(source, doc.Mark()) + ": expected 'key: value' lines (a map_server map YAML)");
  GridYaml y;
  const YAML::Node image = doc["image"];
  if (!image) throw IoError(source + ": no 'image' key");
  if (!image.IsScalar()) throw IoError(yamlAt(source, image.Mark()) + ": image must be a file name");
  y.image = image.Scalar();
  y.resolution = yamlNumberAt<IoError>(doc, "resolution", source);
  const std::vector<double> origin = yamlNumbersAt<IoError>(doc, "origin", 3, source);
  y.origin = {origin[0], origin[1], origin[2]};
  const double negate = yamlNumberAt<IoError>(doc, "negate", source);
  if (negate != 0 && negate != 1) throw IoError(yamlAt(source, doc["negate"].Mark()) + ": negate must be 0 or 1");
  y.negate = static_cast<int>(negate);
  y.occupied_thresh = yamlNumberAt<IoError>(doc, "occupied_thresh", source);
  y.free_thresh = yamlNumberAt<IoError>(doc, "free_thresh", source);
  if (const YAML::Node mode = doc["mode"]; mode && mode.IsScalar()) y.mode = mode.Scalar();
  if (!(y.resolution > 0)) throw IoError(yamlAt(source, doc["resolution"].Mark()) + ": resolution must be > 0");
  return y;
}

OccupancyGrid readGrid(const std::string& yaml_path) {
  const std::string text = readAll(yaml_path);
  const GridYaml y = parseGridYaml(text, yaml_path);
  const size_t slash = yaml_path.find_last_of('/');
  const std::string pgm_path =
      (!y.image.empty() && y.image[0] == '/') || slash == std::string::npos ? y.image
                                                                             : yaml_path.substr(0, slash + 1) + y.image;
  const std::string pgm = readAll(pgm_path);
  // Header: P5, then width, height, maxval separated by whitespace, '#' comments between.
  size_t pos = 0;
  const auto token = [&]() {
    for (;;) {
      while (pos < pgm.size() && std::isspace(static_cast<unsigned char>(pgm[pos]))) ++pos;
      if (pos < pgm.size() && pgm[pos] == '#') {
        while (pos < pgm.size() && pgm[pos] != '\n') ++pos;
        continue;
      }
      break;
    }
    const size_t start = pos;
    while (pos < pgm.size() && !std::isspace(static_cast<unsigned char>(pgm[pos]))) ++pos;
    return pgm.substr(start, pos - start);
  };
  if (token() != "P5") throw IoError(pgm_path + ": not a binary PGM (P5)");
  OccupancyGrid g;
  try {
    g.width = std::stoi(token());
    g.height = std::stoi(token());
    if (std::stoi(token()) != 255) throw IoError(pgm_path + ": only 8-bit PGMs (maxval 255) are read");
  } catch (const std::logic_error&) {
    throw IoError(pgm_path + ": malformed PGM header");
  }
  ++pos;  // the single whitespace after maxval
  if (g.width <= 0 || g.height <= 0 || pgm.size() < pos + static_cast<size_t>(g.width) * g.height)
    throw IoError(pgm_path + ": truncated PGM or bad size");
  g.resolution = y.resolution;
  g.origin = y.origin.head<2>();
  g.cells.assign(static_cast<size_t>(g.width) * g.height, OccupancyGrid::kUnknown);
  for (int row = 0; row < g.height; ++row)
    for (int x = 0; x < g.width; ++x) {
      const double v = static_cast<uint8_t>(pgm[pos + static_cast<size_t>(row) * g.width + x]);
      const double p = y.negate ? v / 255.0 : (255.0 - v) / 255.0;
      int8_t c = OccupancyGrid::kUnknown;
      if (p > y.occupied_thresh) c = OccupancyGrid::kOccupied;
      else if (p < y.free_thresh) c = OccupancyGrid::kFree;
      g.at(x, g.height - 1 - row) = c;
    }
  const size_t tag = text.find("# T_w_grid");
  if (tag != std::string::npos) {
    const size_t colon = text.find("):", tag);
    double v[7];
    if (colon != std::string::npos &&
        std::sscanf(text.c_str() + colon + 2, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                    &v[6]) == 7)
      g.T_w_grid = SE3(Eigen::Quaterniond(v[6], v[3], v[4], v[5]), Eigen::Vector3d(v[0], v[1], v[2]));
  }
  return g;
}

}  // namespace plslam
