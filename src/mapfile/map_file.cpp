#include "mapfile/map_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "mapfile/byte_io.h"
#include "mapfile/container.h"

namespace plslam {

namespace {

using mapfile::ByteReader;
using mapfile::ByteWriter;

// Bounds that keep a corrupt size field from allocating absurd images.
constexpr int kMaxImageSide = 1 << 13;

// Minimum encoded sizes, used to bound counts by the bytes that remain.
constexpr size_t kKeypointBytes = 4 * 8 + 4 + 4 + 4;
constexpr size_t kSegmentBytes = 8 * 8 + 4;
constexpr size_t kInstanceBytes = 4 + 4 + 1 + 4 * 4 + 4 + 3 * 8;
constexpr size_t kDenseBytes = 3 * 4 + 3 + 2;
constexpr size_t kObservationBytes = 8 + 4;
constexpr size_t kRunBytes = 1 + 4;
constexpr size_t kKeyframeMinBytes = 8 + 8 + 7 * 8 + 6 * 4 + 1;
constexpr size_t kPointMinBytes = 8 + 3 * 8 + 8 + 4 + 8 + 4 + 4;
constexpr size_t kLineMinBytes = 8 + 6 * 8 + 8 + 4 + 8 + 4 + 4;

// ---------------------------------------------------------------- writing

void putVec2(ByteWriter* w, const Eigen::Vector2d& v) {
  w->f64(v.x());
  w->f64(v.y());
}
void putVec3(ByteWriter* w, const Eigen::Vector3d& v) {
  w->f64(v.x());
  w->f64(v.y());
  w->f64(v.z());
}
void putPose(ByteWriter* w, const SE3& T) {
  const Eigen::Quaterniond& q = T.quaternion();
  w->f64(q.w());
  w->f64(q.x());
  w->f64(q.y());
  w->f64(q.z());
  putVec3(w, T.translation());
}

/// Descriptors: rows, cols, then the bytes row by row (CV_8UC1 only).
void putDescriptors(ByteWriter* w, const cv::Mat& m, const std::string& what) {
  if (m.empty()) {
    w->i32(0);
    w->i32(0);
    return;
  }
  if (m.type() != CV_8UC1 || m.dims != 2) throw DataError("map file: " + what + " are not CV_8UC1 descriptors");
  w->i32(m.rows);
  w->i32(m.cols);
  for (int r = 0; r < m.rows; ++r) w->bytes(m.ptr<uint8_t>(r), static_cast<size_t>(m.cols));
}

/// The dynamic mask: flag 0 (none) or 1 (run-length coded: rows, cols, runs of value, length).
void putMask(ByteWriter* w, const cv::Mat& m, const std::string& what) {
  if (m.empty()) {
    w->u8(0);
    return;
  }
  if (m.type() != CV_8UC1 || m.dims != 2) throw DataError("map file: " + what + " is not a CV_8UC1 mask");
  w->u8(1);
  w->i32(m.rows);
  w->i32(m.cols);
  std::vector<std::pair<uint8_t, uint32_t>> runs;
  for (int r = 0; r < m.rows; ++r) {
    const uint8_t* row = m.ptr<uint8_t>(r);
    for (int c = 0; c < m.cols; ++c) {
      if (!runs.empty() && runs.back().first == row[c]) ++runs.back().second;
      else runs.emplace_back(row[c], 1);
    }
  }
  w->count(runs.size());
  for (const auto& [value, length] : runs) {
    w->u8(value);
    w->u32(length);
  }
}

void putIds(ByteWriter* w, const std::vector<Id>& ids) {
  w->count(ids.size());
  for (Id id : ids) w->i64(id);
}

void putObservations(ByteWriter* w, const std::map<Id, int>& obs) {
  w->count(obs.size());
  for (const auto& [kf, index] : obs) {
    w->i64(kf);
    w->i32(index);
  }
}

std::string cameraSection(const PinholeCamera& c) {
  ByteWriter w;
  w.str(c.name);
  w.i32(c.width);
  w.i32(c.height);
  w.f64(c.fx);
  w.f64(c.fy);
  w.f64(c.cx);
  w.f64(c.cy);
  for (double d : c.dist) w.f64(d);
  w.f64(c.depth_scale);
  return w.take();
}

void putKeyframe(ByteWriter* w, const KeyFrame& kf) {
  const std::string what = "keyframe " + std::to_string(kf.id);
  w->i64(kf.id);
  w->i64(kf.t_ns);
  putPose(w, kf.T_w_c);
  const FrameFeatures& f = kf.features;
  w->count(f.points.size());
  for (const Keypoint& k : f.points) {
    putVec2(w, k.uv_raw);
    putVec2(w, k.uv);
    w->i32(k.octave);
    w->f32(k.angle);
    w->f32(k.depth_m);
  }
  putDescriptors(w, f.point_descriptors, what + " point descriptors");
  w->count(f.lines.size());
  for (const Segment2D& s : f.lines) {
    putVec2(w, s.p_raw);
    putVec2(w, s.q_raw);
    putVec2(w, s.p);
    putVec2(w, s.q);
    w->i32(s.octave);
  }
  putDescriptors(w, f.line_descriptors, what + " line descriptors");
  putIds(w, kf.point_ids);
  putIds(w, kf.line_ids);
  w->count(kf.instances.size());
  for (const KeyframeInstance& in : kf.instances) {
    w->i32(in.class_id);
    w->str(in.class_name);
    w->u8(in.dynamic ? 1 : 0);
    w->i32(in.box.x);
    w->i32(in.box.y);
    w->i32(in.box.width);
    w->i32(in.box.height);
    w->i32(in.pixels);
    putVec3(w, in.centroid_c);
  }
  w->count(kf.dense.size());
  for (const DensePoint& d : kf.dense) {
    w->f32(d.p_c.x());
    w->f32(d.p_c.y());
    w->f32(d.p_c.z());
    w->u8(d.r);
    w->u8(d.g);
    w->u8(d.b);
    w->i16(d.class_id);
  }
  putMask(w, kf.dynamic_mask, what + " dynamic mask");
}

template <typename Landmark>
void putLandmarkTail(ByteWriter* w, const Landmark& l, const std::string& what) {
  putDescriptors(w, l.descriptor, what + " descriptor");
  putObservations(w, l.observations);
  w->i64(l.first_keyframe);
  w->i32(l.visible);
  w->i32(l.found);
}

// ---------------------------------------------------------------- reading

Eigen::Vector2d getVec2(ByteReader* r) {
  const double x = r->f64();
  return {x, r->f64()};
}
Eigen::Vector3d getVec3(ByteReader* r) {
  const double x = r->f64();
  const double y = r->f64();
  return {x, y, r->f64()};
}
SE3 getPose(ByteReader* r) {
  const double qw = r->f64(), qx = r->f64(), qy = r->f64(), qz = r->f64();
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  const Eigen::Vector3d t = getVec3(r);
  if (!std::isfinite(q.norm()) || q.norm() < 1e-6 || !t.allFinite()) r->fail("a pose is not finite or has a zero quaternion");
  return SE3(q, t);
}

cv::Mat getDescriptors(ByteReader* r) {
  const int rows = r->i32(), cols = r->i32();
  if (rows < 0 || cols < 0) r->fail("negative descriptor matrix size");
  if (rows == 0 || cols == 0) return cv::Mat();
  if (static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols) > r->remaining())
    r->fail("descriptor matrix " + std::to_string(rows) + "x" + std::to_string(cols) + " is larger than the rest of the section");
  cv::Mat m(rows, cols, CV_8UC1);
  for (int i = 0; i < rows; ++i) r->bytes(m.ptr<uint8_t>(i), static_cast<size_t>(cols), "descriptors");
  return m;
}

/// The mask must have the camera's image size: checked before anything is allocated.
cv::Mat getMask(ByteReader* r, const PinholeCamera& camera) {
  const uint8_t flag = r->u8();
  if (flag == 0) return cv::Mat();
  if (flag != 1) r->fail("unknown dynamic mask encoding " + std::to_string(flag));
  const int rows = r->i32(), cols = r->i32();
  if (rows != camera.height || cols != camera.width)
    r->fail("dynamic mask " + std::to_string(cols) + "x" + std::to_string(rows) + " differs from the camera's image size " +
            std::to_string(camera.width) + "x" + std::to_string(camera.height));
  const size_t n_runs = r->count(kRunBytes, "mask runs");
  std::vector<std::pair<uint8_t, uint32_t>> runs;
  runs.reserve(n_runs);
  const uint64_t total = static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols);
  uint64_t sum = 0;
  for (size_t i = 0; i < n_runs; ++i) {
    const uint8_t value = r->u8();
    const uint32_t length = r->u32();
    sum += length;
    if (length == 0 || sum > total) r->fail("dynamic mask runs do not add up to its " + std::to_string(total) + " pixels");
    runs.emplace_back(value, length);
  }
  if (sum != total) r->fail("dynamic mask runs do not add up to its " + std::to_string(total) + " pixels");
  cv::Mat m(rows, cols, CV_8UC1);
  uint8_t* p = m.ptr<uint8_t>(0);  // freshly allocated: continuous
  for (const auto& [value, length] : runs) p = std::fill_n(p, length, value);
  return m;
}

std::vector<Id> getIds(ByteReader* r, const char* what) {
  const size_t n = r->count(8, what);
  std::vector<Id> ids(n);
  for (Id& id : ids) id = r->i64();
  return ids;
}

std::map<Id, int> getObservations(ByteReader* r) {
  const size_t n = r->count(kObservationBytes, "observations");
  std::map<Id, int> obs;
  for (size_t i = 0; i < n; ++i) {
    const Id kf = r->i64();
    const int index = r->i32();
    if (!obs.emplace(kf, index).second) r->fail("keyframe " + std::to_string(kf) + " observes a landmark twice");
  }
  return obs;
}

PinholeCamera getCamera(ByteReader* r) {
  PinholeCamera c;
  c.name = r->str("camera name");
  c.width = r->i32();
  c.height = r->i32();
  c.fx = r->f64();
  c.fy = r->f64();
  c.cx = r->f64();
  c.cy = r->f64();
  for (double& d : c.dist) d = r->f64();
  c.depth_scale = r->f64();
  r->expectEnd();
  if (c.width > kMaxImageSide || c.height > kMaxImageSide) r->fail("image size out of range");  // bounds mask allocations
  return c;
}

KeyFrame getKeyframe(ByteReader* r, const PinholeCamera& camera) {
  KeyFrame kf;
  kf.id = r->i64();
  kf.t_ns = r->i64();
  kf.T_w_c = getPose(r);
  FrameFeatures& f = kf.features;
  f.points.resize(r->count(kKeypointBytes, "keypoints"));
  for (Keypoint& k : f.points) {
    k.uv_raw = getVec2(r);
    k.uv = getVec2(r);
    k.octave = r->i32();
    k.angle = r->f32();
    k.depth_m = r->f32();
  }
  f.point_descriptors = getDescriptors(r);
  f.lines.resize(r->count(kSegmentBytes, "segments"));
  for (Segment2D& s : f.lines) {
    s.p_raw = getVec2(r);
    s.q_raw = getVec2(r);
    s.p = getVec2(r);
    s.q = getVec2(r);
    s.octave = r->i32();
  }
  f.line_descriptors = getDescriptors(r);
  kf.point_ids = getIds(r, "point ids");
  kf.line_ids = getIds(r, "line ids");
  kf.instances.resize(r->count(kInstanceBytes, "instances"));
  for (KeyframeInstance& in : kf.instances) {
    in.class_id = r->i32();
    in.class_name = r->str("class name");
    in.dynamic = r->u8() != 0;
    in.box.x = r->i32();
    in.box.y = r->i32();
    in.box.width = r->i32();
    in.box.height = r->i32();
    in.pixels = r->i32();
    in.centroid_c = getVec3(r);
  }
  kf.dense.resize(r->count(kDenseBytes, "dense points"));
  for (DensePoint& d : kf.dense) {
    const float x = r->f32(), y = r->f32(), z = r->f32();
    d.p_c = Eigen::Vector3f(x, y, z);
    d.r = r->u8();
    d.g = r->u8();
    d.b = r->u8();
    d.class_id = r->i16();
  }
  kf.dynamic_mask = getMask(r, camera);
  return kf;
}

template <typename Landmark>
void getLandmarkTail(ByteReader* r, Landmark* l) {
  l->descriptor = getDescriptors(r);
  l->observations = getObservations(r);
  l->first_keyframe = r->i64();
  l->visible = r->i32();
  l->found = r->i32();
}

const mapfile::Section& required(const mapfile::Container& c, const char* name, const std::string& file) {
  const mapfile::Section* s = c.find(name);
  if (!s) throw IoError(file + ": section '" + name + "' is missing");
  return *s;
}

// ---------------------------------------------------------------- consistency

/// Both sides of every observation agree, and every id names an entity of the file.
template <typename Landmark>
void checkObservations(const std::map<Id, Landmark>& landmarks, const std::map<Id, KeyFrame>& keyframes,
                       const char* noun, std::vector<Id> KeyFrame::*ids, const std::string& file) {
  for (const auto& [id, l] : landmarks) {
    for (const auto& [kf_id, index] : l.observations) {
      auto kf = keyframes.find(kf_id);
      if (kf == keyframes.end())
        throw DataError(file + ": inconsistent ids: " + noun + " " + std::to_string(id) + " is observed by keyframe " +
                        std::to_string(kf_id) + ", which is not in the file");
      const std::vector<Id>& v = kf->second.*ids;
      if (index < 0 || static_cast<size_t>(index) >= v.size() || v[index] != id)
        throw DataError(file + ": inconsistent ids: " + noun + " " + std::to_string(id) + " is observed by feature " +
                        std::to_string(index) + " of keyframe " + std::to_string(kf_id) + ", which does not name it");
    }
  }
  for (const auto& [kf_id, kf] : keyframes) {
    const std::vector<Id>& v = kf.*ids;
    for (size_t i = 0; i < v.size(); ++i) {
      if (v[i] == kNoId) continue;
      auto l = landmarks.find(v[i]);
      if (l == landmarks.end())
        throw DataError(file + ": inconsistent ids: keyframe " + std::to_string(kf_id) + " names " + noun + " " +
                        std::to_string(v[i]) + ", which is not in the file");
      auto o = l->second.observations.find(kf_id);
      if (o == l->second.observations.end() || o->second != static_cast<int>(i))
        throw DataError(file + ": inconsistent ids: keyframe " + std::to_string(kf_id) + " feature " + std::to_string(i) +
                        " names " + noun + " " + std::to_string(v[i]) + ", which does not list that observation");
    }
  }
}

void checkKeyframe(const KeyFrame& kf, const PinholeCamera& camera, const std::string& file) {
  const std::string what = file + ": keyframe " + std::to_string(kf.id) + ": ";
  const FrameFeatures& f = kf.features;
  if (kf.point_ids.size() != f.points.size() || kf.line_ids.size() != f.lines.size())
    throw DataError(what + "feature and id counts differ");
  if (static_cast<size_t>(f.point_descriptors.rows) != f.points.size() ||
      static_cast<size_t>(f.line_descriptors.rows) != f.lines.size())
    throw DataError(what + "descriptor and feature counts differ");
  if (!kf.dynamic_mask.empty() && (kf.dynamic_mask.cols != camera.width || kf.dynamic_mask.rows != camera.height))
    throw DataError(what + "dynamic mask " + std::to_string(kf.dynamic_mask.cols) + "x" +
                    std::to_string(kf.dynamic_mask.rows) + " differs from the camera's image size");
  for (Id id : kf.point_ids)
    if (id < kNoId) throw DataError(what + "negative point id " + std::to_string(id));
  for (Id id : kf.line_ids)
    if (id < kNoId) throw DataError(what + "negative line id " + std::to_string(id));
}

}  // namespace

std::string serializeMap(const Map& map, const PinholeCamera& camera, const std::string& config_yaml,
                         const MapFrame* frame) {
  mapfile::Container c;
  std::lock_guard<std::mutex> lock(map.mutex());
  c.keyframes = static_cast<int64_t>(map.keyframes().size());
  c.points = static_cast<int64_t>(map.points().size());
  c.lines = static_cast<int64_t>(map.lines().size());
  c.sections.push_back({"camera", cameraSection(camera)});
  c.sections.push_back({"config", config_yaml});
  {
    ByteWriter w;
    w.count(map.keyframes().size());
    for (const auto& [id, kf] : map.keyframes()) putKeyframe(&w, kf);
    c.sections.push_back({"keyframes", w.take()});
  }
  {
    ByteWriter w;
    w.count(map.points().size());
    for (const auto& [id, p] : map.points()) {
      w.i64(p.id);
      putVec3(&w, p.p_w);
      putLandmarkTail(&w, p, "map point " + std::to_string(id));
    }
    c.sections.push_back({"points", w.take()});
  }
  {
    ByteWriter w;
    w.count(map.lines().size());
    for (const auto& [id, l] : map.lines()) {
      w.i64(l.id);
      putVec3(&w, l.P_w);
      putVec3(&w, l.Q_w);
      putLandmarkTail(&w, l, "map line " + std::to_string(id));
    }
    c.sections.push_back({"lines", w.take()});
  }
  if (frame) c.sections.push_back({"map_frame", mapFrameToYaml(*frame)});
  return mapfile::packContainer(c);
}

void saveMap(const std::string& path, const Map& map, const PinholeCamera& camera, const std::string& config_yaml,
             const MapFrame* frame) {
  writeFileAtomically(path, serializeMap(map, camera, config_yaml, frame));
}

LoadedMap loadMap(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the map file (missing or unreadable)");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(path + ": read error");
  return parseMap(bytes, path);
}

namespace {

PinholeCamera readCameraSection(const mapfile::Container& c, const std::string& file) {
  const mapfile::Section& s = required(c, "camera", file);
  ByteReader r(s.bytes.data(), s.bytes.size(), file, s.name);
  PinholeCamera camera = getCamera(&r);
  try {
    camera.validate(file + " (camera section)");
  } catch (const Error& e) {
    throw DataError(e.what());
  }
  return camera;
}

std::map<Id, KeyFrame> readKeyframeSection(const mapfile::Container& c, const PinholeCamera& camera,
                                           const std::string& file) {
  std::map<Id, KeyFrame> keyframes;
  const mapfile::Section& s = required(c, "keyframes", file);
  ByteReader r(s.bytes.data(), s.bytes.size(), file, s.name);
  const size_t n = r.count(kKeyframeMinBytes, "keyframes");
  for (size_t i = 0; i < n; ++i) {
    KeyFrame kf = getKeyframe(&r, camera);
    if (kf.id < 0) throw DataError(file + ": keyframe with negative id " + std::to_string(kf.id));
    checkKeyframe(kf, camera, file);
    const Id id = kf.id;
    if (!keyframes.emplace(id, std::move(kf)).second)
      throw DataError(file + ": inconsistent ids: keyframe id " + std::to_string(id) + " appears twice");
  }
  r.expectEnd();
  return keyframes;
}

std::map<Id, MapPoint> readPointSection(const mapfile::Container& c, const std::string& file) {
  std::map<Id, MapPoint> points;
  const mapfile::Section& s = required(c, "points", file);
  ByteReader r(s.bytes.data(), s.bytes.size(), file, s.name);
  const size_t n = r.count(kPointMinBytes, "map points");
  for (size_t i = 0; i < n; ++i) {
    MapPoint p;
    p.id = r.i64();
    p.p_w = getVec3(&r);
    getLandmarkTail(&r, &p);
    if (p.id < 0) throw DataError(file + ": map point with negative id " + std::to_string(p.id));
    const Id id = p.id;
    if (!points.emplace(id, std::move(p)).second)
      throw DataError(file + ": inconsistent ids: map point id " + std::to_string(id) + " appears twice");
  }
  r.expectEnd();
  return points;
}

std::map<Id, MapLine> readLineSection(const mapfile::Container& c, const std::string& file) {
  std::map<Id, MapLine> lines;
  const mapfile::Section& s = required(c, "lines", file);
  ByteReader r(s.bytes.data(), s.bytes.size(), file, s.name);
  const size_t n = r.count(kLineMinBytes, "map lines");
  for (size_t i = 0; i < n; ++i) {
    MapLine l;
    l.id = r.i64();
    l.P_w = getVec3(&r);
    l.Q_w = getVec3(&r);
    getLandmarkTail(&r, &l);
    if (l.id < 0) throw DataError(file + ": map line with negative id " + std::to_string(l.id));
    const Id id = l.id;
    if (!lines.emplace(id, std::move(l)).second)
      throw DataError(file + ": inconsistent ids: map line id " + std::to_string(id) + " appears twice");
  }
  r.expectEnd();
  return lines;
}

}  // namespace

LoadedMap parseMap(const std::string& bytes, const std::string& file) {
  const mapfile::Container c = mapfile::unpackContainer(bytes, file);
  LoadedMap out;
  out.writer = c.writer;
  out.camera = readCameraSection(c, file);
  out.config_yaml = required(c, "config", file).bytes;
  if (const mapfile::Section* s = c.find("map_frame")) out.frame = parseMapFrameYaml(s->bytes, file + " (map_frame section)");

  std::map<Id, KeyFrame> keyframes = readKeyframeSection(c, out.camera, file);
  std::map<Id, MapPoint> points = readPointSection(c, file);
  std::map<Id, MapLine> lines = readLineSection(c, file);
  if (static_cast<int64_t>(keyframes.size()) != c.keyframes || static_cast<int64_t>(points.size()) != c.points ||
      static_cast<int64_t>(lines.size()) != c.lines)
    throw DataError(file + ": the header's counts (" + std::to_string(c.keyframes) + " keyframes, " +
                    std::to_string(c.points) + " points, " + std::to_string(c.lines) +
                    " lines) differ from the sections' (" + std::to_string(keyframes.size()) + ", " +
                    std::to_string(points.size()) + ", " + std::to_string(lines.size()) + ")");
  checkObservations(points, keyframes, "map point", &KeyFrame::point_ids, file);
  checkObservations(lines, keyframes, "map line", &KeyFrame::line_ids, file);

  for (auto& [id, kf] : keyframes) out.map.restoreKeyFrame(std::move(kf));
  for (auto& [id, p] : points) out.map.restorePoint(std::move(p));
  for (auto& [id, l] : lines) out.map.restoreLine(std::move(l));
  return out;
}

}  // namespace plslam
