#include "fuzz_targets.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "camera/camera_file.h"
#include "core/error.h"
#include "core/log.h"
#include "dynamic/class_list.h"
#include "dynamic/onnx_check.h"
#include "io/dataset.h"
#include "io/trajectory_file.h"
#include "io/tum_line.h"
#ifdef PLSLAM_FUZZ_HAVE_MAPFILE
#include "mapfile/container.h"
#include "mapfile/map_file.h"
#endif

namespace fs = std::filesystem;

namespace plslam::fuzz {
namespace {

// A per-process scratch folder for the parsers that read files by path (in RAM when /dev/shm exists).
const std::string& scratch() {
  static const std::string dir = [] {
    const fs::path base = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    const fs::path d = base / ("plslam_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d.string();
  }();
  return dir;
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Splits the input into `n` parts at "\n---\n" separators (missing parts are empty), so one
// input can carry several files.
std::vector<std::string> parts(const std::string& bytes, size_t n) {
  std::vector<std::string> out;
  size_t at = 0;
  while (out.size() + 1 < n) {
    const size_t sep = bytes.find("\n---\n", at);
    if (sep == std::string::npos) break;
    out.push_back(bytes.substr(at, sep - at));
    at = sep + 5;
  }
  out.push_back(at <= bytes.size() ? bytes.substr(at) : "");
  out.resize(n);
  return out;
}

PinholeCamera smallCamera() {
  PinholeCamera c;
  c.width = 64;
  c.height = 48;
  c.fx = c.fy = 50;
  c.cx = 32;
  c.cy = 24;
  return c;
}

// TUM/ICL list files: the first byte picks the layout, the rest is split into the lists.
// Part layout (TUM): rgb.txt, depth.txt, masks.txt, groundtruth.txt;
// (ICL): associations.txt, groundtruth.txt.
void tumList(const std::string& bytes) {
  std::vector<std::string> fields;
  for (size_t b = 0, e; b <= bytes.size(); b = e + 1) {
    e = bytes.find('\n', b);
    if (e == std::string::npos) e = bytes.size();
    splitTumLine(bytes.substr(b, e - b), &fields);
  }
  if (bytes.empty()) return;
  const fs::path dir = fs::path(scratch()) / "list";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const bool icl = bytes[0] & 1;
  const auto p = parts(bytes.substr(1), icl ? 2 : 4);
  if (icl) {
    writeFile((dir / "associations.txt").string(), p[0]);
    if (!p[1].empty()) writeFile((dir / "groundtruth.txt").string(), p[1]);
  } else {
    writeFile((dir / "rgb.txt").string(), p[0]);
    writeFile((dir / "depth.txt").string(), p[1]);
    if (!p[2].empty()) writeFile((dir / "masks.txt").string(), p[2]);
    if (!p[3].empty()) writeFile((dir / "groundtruth.txt").string(), p[3]);
  }
  DatasetOptions options;
  options.max_frames = bytes[0] & 2 ? 3 : 0;
  TumDataset ds = TumDataset::open(dir.string(), smallCamera(), options);
  // The listed images do not exist (or are whatever the paths name): every load must be a
  // counted skip or a frame, never a crash.
  RgbdFrame frame;
  for (size_t i = 0; i < ds.size() && i < 4; ++i) ds.load(i, &frame);
  (void)ds.stamps();
}

void trajectory(const std::string& bytes) {
  TrajectoryReadReport report;
  const Trajectory t = parseTumTrajectory(bytes, "fuzz.txt", &report);
  for (size_t i = 1; i < t.size(); ++i)
    if (!(t[i - 1].t_ns < t[i].t_ns)) std::abort();  // the documented contract: sorted, no duplicates
}

void cameraFile(const std::string& bytes) {
  const PinholeCamera c = parseCameraFile(bytes, "fuzz.xml");
  // A camera that passed validation must be usable.
  const Eigen::Vector2d uv = c.undistort(Eigen::Vector2d(c.cx, c.cy));
  (void)c.unproject(uv, 1.0);
  (void)c.project(Eigen::Vector3d(0.1, -0.1, 1.0));
}

void classList(const std::string& bytes) {
  const std::string path = scratch() + "/names.txt";
  writeFile(path, bytes);
  ClassList list = ClassList::load(path);
  (void)list.find("person");
  (void)list.name(static_cast<int>(list.size()));
  list.setDynamic({list.names().front()});
}

void onnx(const std::string& bytes) {
  const OnnxModelInfo info = inspectOnnxBytes(bytes, "fuzz.onnx");
  std::vector<std::vector<int64_t>> shapes;
  for (const auto& o : info.outputs) shapes.push_back(o.dims);
  for (const auto& s : shapes) (void)shapeToString(s);
  (void)checkYoloSegOutputs(shapes, "fuzz.onnx");
}

#ifdef PLSLAM_FUZZ_HAVE_MAPFILE
// Whole files, and (first byte 'S') raw sections packed with valid CRCs, so the fuzzer
// reaches the section decoders instead of stopping at the checksums.
void mapFile(const std::string& bytes) {
  if (bytes.empty() || bytes[0] != 'S') {
    (void)parseMap(bytes, "fuzz.plmap");
    return;
  }
  mapfile::Container c;
  const char* names[] = {"camera", "config", "keyframes", "points", "lines"};
  const auto p = parts(bytes.substr(1), 5);
  for (int i = 0; i < 5; ++i) c.sections.push_back({names[i], p[i]});
  (void)parseMap(mapfile::packContainer(c), "fuzz.plmap");
}
#endif

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> list = {
      {"tum_list", tumList},       {"trajectory", trajectory}, {"camera_file", cameraFile},
#ifdef PLSLAM_FUZZ_WITH_CONFIG
      {"config", config},
#endif
      {"class_list", classList},
      {"onnx", onnx},
#ifdef PLSLAM_FUZZ_HAVE_MAPFILE
      {"map_file", mapFile},
#endif
  };
  return list;
}

const Target* findTarget(const std::string& name) {
  for (const Target& t : targets())
    if (name == t.name) return &t;
  return nullptr;
}

bool runOne(const Target& target, const std::string& bytes) {
  try {
    target.run(bytes);
    return true;
  } catch (const Error&) {
    return false;  // refused with a typed error naming the input: the expected outcome for bad bytes
  }
}

}  // namespace plslam::fuzz
