#include "core/map_frame.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace plslam {

namespace {

constexpr char kFormat[] = "plslam_map_frame 1";

std::string number(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", x);
  return b;
}

std::string list(std::initializer_list<double> v) {
  std::string s;
  for (double x : v) s += (s.empty() ? "[" : ", ") + number(x);
  return s + "]";
}

// "key: value" lines, comments ('#' to the end of a line) and blank lines skipped.
std::map<std::string, std::string> keyValues(const std::string& text) {
  std::map<std::string, std::string> kv;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const auto trim = [](std::string s) {
      const size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    };
    kv[trim(line.substr(0, colon))] = trim(line.substr(colon + 1));
  }
  return kv;
}

std::vector<double> numbers(const std::map<std::string, std::string>& kv, const std::string& key, size_t n,
                            const std::string& source) {
  const auto it = kv.find(key);
  const std::string bad = source + ": map frame key '" + key + "' ";
  if (it == kv.end()) throw IoError(bad + "is missing");
  const std::string& s = it->second;
  if (s.size() < 2 || s.front() != '[' || s.back() != ']') throw IoError(bad + "must be a list [..]: " + s);
  std::vector<double> v;
  std::istringstream in(s.substr(1, s.size() - 2));
  for (std::string item; std::getline(in, item, ',');) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || !std::isfinite(x)) throw IoError(bad + "has a bad number: " + s);
    v.push_back(x);
  }
  if (v.size() != n) throw IoError(bad + "needs " + std::to_string(n) + " numbers: " + s);
  return v;
}

}  // namespace

std::string mapFrameToYaml(const MapFrame& f) {
  const Eigen::Vector3d& t = f.T_map_world.translation();
  const Eigen::Quaterniond& q = f.T_map_world.quaternion();
  std::ostringstream s;
  s << "# plslam map frame: p_map = T_map_world * p_world.\n"
    << "# world: the SLAM world (the first keyframe's camera: x right, y down, z forward), frame of trajectory.txt.\n"
    << "# map (REP-103/105): z up along the floor normal, y left; origin: base = x the robot base's forward at the\n"
    << "# first keyframe laid onto the floor, origin on the floor below the base; origin: camera = x the first camera's\n"
    << "# optical axis laid onto the floor, origin on the floor below it. Every other world-frame output is in it.\n"
    << "format: " << kFormat << "\nparent_frame: map\nchild_frame: world\n"
    << "translation: " << list({t.x(), t.y(), t.z()}) << "\n"
    << "rotation: " << list({q.x(), q.y(), q.z(), q.w()}) << "\n"
    << "camera_height_m: " << number(f.cameraHeight()) << "\nfloor_method: " << f.floor_method
    << "\nfloor_source: " << f.floor_source << "\nfloor_points: " << f.floor_points << "\norigin: " << f.origin << "\n";
  return s.str();
}

MapFrame parseMapFrameYaml(const std::string& text, const std::string& source) {
  const std::map<std::string, std::string> kv = keyValues(text);
  const auto format = kv.find("format");
  if (format == kv.end() || format->second != kFormat)
    throw IoError(source + ": not a map frame file (needs 'format: " + kFormat + "')");
  const std::vector<double> t = numbers(kv, "translation", 3, source);
  const std::vector<double> q = numbers(kv, "rotation", 4, source);
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-3) throw IoError(source + ": map frame rotation is not a unit quaternion");
  MapFrame f;
  f.T_map_world = SE3(quat, Eigen::Vector3d(t[0], t[1], t[2]));
  const auto get = [&](const char* key) {
    const auto it = kv.find(key);
    return it == kv.end() ? std::string() : it->second;
  };
  f.floor_method = get("floor_method");
  f.floor_source = get("floor_source");
  f.floor_points = std::atoi(get("floor_points").c_str());
  f.origin = get("origin").empty() ? "camera" : get("origin");  // files written before the key: camera
  return f;
}

}  // namespace plslam
