// The map file: exact round trip of a map built by SLAM, and refusal (with a message naming
// the file and the problem) of missing, foreign, future, truncated, corrupt and
// inconsistent files; no byte string makes the parser crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <fstream>
#include <random>

#include "core/error.h"
#include "map_fixture.h"
#include "mapfile/byte_io.h"
#include "mapfile/container.h"
#include "mapfile/map_file.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

const std::string kName = "test.plmap";

/// The serialized shared map (computed once).
const std::string& mapBytes() {
  static const std::string bytes = [] {
    const test::BuiltMap& b = test::builtMap();
    return serializeMap(*b.map, b.camera, b.config_yaml);
  }();
  return bytes;
}

/// Offset and length of each section in a valid file, in file order.
struct SectionSpan {
  std::string name;
  size_t offset, size;
};
std::vector<SectionSpan> sectionSpans(const std::string& bytes) {
  const mapfile::Container c = mapfile::unpackContainer(bytes, kName);
  uint32_t header_len = 0;
  for (int i = 0; i < 4; ++i) header_len |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[12 + i])) << (8 * i);
  size_t at = 16 + header_len + 4;
  std::vector<SectionSpan> out;
  for (const mapfile::Section& s : c.sections) {
    out.push_back({s.name, at, s.bytes.size()});
    at += s.bytes.size();
  }
  return out;
}

/// The message of the Error parseMap throws on `bytes` (fails the test when none, or when
/// it is not of type E).
template <typename E>
std::string refusal(const std::string& bytes) {
  try {
    parseMap(bytes, kName);
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
    return "";
  }
  ADD_FAILURE() << "accepted";
  return "";
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

}  // namespace

TEST(MapFile, RoundTripKeepsEveryField) {
  const test::BuiltMap& b = test::freshlyBuiltMap();
  ASSERT_GT(b.map->keyframes().size(), 2u);
  ASSERT_GT(b.map->points().size(), 100u);
  ASSERT_GT(b.map->lines().size(), 5u) << "the synthetic scene should give 3D lines";
  const std::string dir = test::scratchDir("mapfile_roundtrip");
  const std::string path = dir + "/map.plmap";
  saveMap(path, *b.map, b.camera, b.config_yaml);
  const LoadedMap loaded = loadMap(path);
  test::expectMapsEqual(*b.map, loaded.map);
  EXPECT_EQ(loaded.config_yaml, b.config_yaml);
  EXPECT_EQ(loaded.camera.name, b.camera.name);
  EXPECT_EQ(loaded.camera.width, b.camera.width);
  EXPECT_EQ(loaded.camera.height, b.camera.height);
  EXPECT_EQ(loaded.camera.fx, b.camera.fx);
  EXPECT_EQ(loaded.camera.fy, b.camera.fy);
  EXPECT_EQ(loaded.camera.cx, b.camera.cx);
  EXPECT_EQ(loaded.camera.cy, b.camera.cy);
  EXPECT_EQ(loaded.camera.dist, b.camera.dist);
  EXPECT_EQ(loaded.camera.depth_scale, b.camera.depth_scale);
  EXPECT_FALSE(loaded.writer.empty());
  // Written again, the loaded map gives the same bytes (nothing lost, deterministic).
  EXPECT_TRUE(serializeMap(loaded.map, loaded.camera, loaded.config_yaml) == test::readFile(path));
}

TEST(MapFile, CameraWithDistortionAndDepthScaleRoundTrips) {
  PinholeCamera c;
  c.name = "tum_freiburg1";
  c.width = 640;
  c.height = 480;
  c.fx = 517.3;
  c.fy = 516.5;
  c.cx = 318.6;
  c.cy = 255.3;
  c.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  c.depth_scale = 1000.0;
  const LoadedMap l = parseMap(serializeMap(Map(), c, ""), kName);
  EXPECT_EQ(l.camera.name, c.name);
  EXPECT_EQ(l.camera.dist, c.dist);
  EXPECT_EQ(l.camera.depth_scale, 1000.0);
  EXPECT_EQ(l.camera.fx, c.fx);
  EXPECT_TRUE(l.map.keyframes().empty());
  EXPECT_TRUE(l.config_yaml.empty());
}

TEST(MapFile, RestoredIdsAreKeptAndNewOnesComeAfter) {
  const test::BuiltMap& b = test::builtMap();
  LoadedMap l = parseMap(mapBytes(), kName);
  const Id last_kf = l.map.keyframes().rbegin()->first;
  const Id last_pt = l.map.points().rbegin()->first;
  const Id last_ln = l.map.lines().rbegin()->first;
  EXPECT_EQ(last_kf, b.map->keyframes().rbegin()->first);
  EXPECT_GT(l.map.addKeyFrame(KeyFrame()), last_kf);
  EXPECT_GT(l.map.addPoint(MapPoint()), last_pt);
  EXPECT_GT(l.map.addLine(MapLine()), last_ln);
  MapPoint again;
  again.id = last_pt;
  EXPECT_THROW(l.map.restorePoint(again), DataError);
}

TEST(MapFile, MissingFileIsRefusedNamingIt) {
  const std::string path = test::scratchDir("mapfile_missing") + "/nothing_here.plmap";
  try {
    loadMap(path);
    FAIL() << "a missing file was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

TEST(MapFile, WrongMagicIsNotAMap) {
  std::string bytes = mapBytes();
  bytes[0] = 'X';
  const std::string msg = refusal<IoError>(bytes);
  EXPECT_NE(msg.find(kName), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a plslam map"), std::string::npos) << msg;
  EXPECT_NE(refusal<IoError>("ply\nformat ascii 1.0\n").find("not a plslam map"), std::string::npos);
  EXPECT_NE(refusal<IoError>("").find("not a plslam map"), std::string::npos);
  // A map saved through a real file is refused the same way by loadMap.
  const std::string path = test::scratchDir("mapfile_magic") + "/not_a_map.plmap";
  writeBytes(path, "hello world, this is text");
  try {
    loadMap(path);
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": not a plslam map"), std::string::npos) << e.what();
  }
}

TEST(MapFile, FutureVersionSaysWhichVersionAndWhichThisBuildReads) {
  std::string bytes = mapBytes();
  bytes[8] = 7;  // format version 7, little-endian u32 at offset 8
  const std::string msg = refusal<IoError>(bytes);
  EXPECT_NE(msg.find("version 7"), std::string::npos) << msg;
  EXPECT_NE(msg.find("reads version " + std::to_string(mapfile::kFormatVersion)), std::string::npos) << msg;
}

TEST(MapFile, TruncatedFilesNameTheSectionWhereTheyEnd) {
  const std::string& bytes = mapBytes();
  EXPECT_NE(refusal<IoError>(bytes.substr(0, 5)).find("truncated in the preamble"), std::string::npos)
      << "5 bytes of the magic";
  EXPECT_NE(refusal<IoError>(bytes.substr(0, 8)).find("truncated in the preamble"), std::string::npos);
  EXPECT_NE(refusal<IoError>(bytes.substr(0, 12)).find("truncated in the preamble"), std::string::npos);
  EXPECT_NE(refusal<IoError>(bytes.substr(0, 40)).find("truncated in the header"), std::string::npos);
  for (const SectionSpan& s : sectionSpans(bytes)) {
    if (s.size == 0) continue;
    for (size_t cut : {s.offset, s.offset + s.size / 2, s.offset + s.size - 1}) {
      const std::string msg = refusal<IoError>(bytes.substr(0, cut));
      EXPECT_NE(msg.find("truncated in section '" + s.name + "'"), std::string::npos)
          << "cut at " << cut << ": " << msg;
      EXPECT_NE(msg.find(kName), std::string::npos) << msg;
    }
  }
  EXPECT_NE(refusal<IoError>(bytes + "x").find("unexpected bytes after the last section"), std::string::npos);
}

TEST(MapFile, BitFlipsAreCaughtByTheSectionCrc) {
  const std::string& bytes = mapBytes();
  const std::vector<SectionSpan> spans = sectionSpans(bytes);
  ASSERT_EQ(spans.size(), 5u);
  for (const SectionSpan& s : spans) {
    if (s.size == 0) continue;  // an empty config has no bit to flip
    for (size_t at : {s.offset, s.offset + s.size / 3, s.offset + s.size - 1}) {
      std::string flipped = bytes;
      flipped[at] ^= 0x10;
      const std::string msg = refusal<IoError>(flipped);
      EXPECT_NE(msg.find("CRC mismatch in section '" + s.name + "'"), std::string::npos) << "byte " << at << ": " << msg;
    }
  }
  std::string header_flip = bytes;
  header_flip[30] ^= 0x01;  // inside the header text
  EXPECT_NE(refusal<IoError>(header_flip).find("CRC mismatch in the header"), std::string::npos);
}

TEST(MapFile, InconsistentIdsAreRefused) {
  const test::BuiltMap& b = test::builtMap();
  Map map;
  KeyFrame kf;
  kf.id = 3;
  kf.features.points.resize(2);
  kf.features.point_descriptors = cv::Mat::zeros(2, 32, CV_8U);
  kf.point_ids = {10, kNoId};
  map.restoreKeyFrame(kf);
  MapPoint p;
  p.id = 10;
  p.descriptor = cv::Mat::zeros(1, 32, CV_8U);
  p.observations = {{3, 0}, {99, 0}};  // keyframe 99 does not exist
  map.restorePoint(p);
  std::string msg = refusal<DataError>(serializeMap(map, b.camera, ""));
  EXPECT_NE(msg.find("inconsistent ids"), std::string::npos) << msg;
  EXPECT_NE(msg.find("keyframe 99"), std::string::npos) << msg;
  EXPECT_NE(msg.find(kName), std::string::npos) << msg;

  // A keyframe naming a point that does not list it.
  map.point(10)->observations = {};
  msg = refusal<DataError>(serializeMap(map, b.camera, ""));
  EXPECT_NE(msg.find("keyframe 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("map point 10"), std::string::npos) << msg;

  // A point whose keyframe has been lost from the file (its observation names it).
  Map orphan;
  MapPoint q = p;
  q.observations = {{5, 0}};
  orphan.restorePoint(q);
  msg = refusal<DataError>(serializeMap(orphan, b.camera, ""));
  EXPECT_NE(msg.find("keyframe 5, which is not in the file"), std::string::npos) << msg;
}

TEST(MapFile, AtomicSaveReplacesAnOldFileWhole) {
  const test::BuiltMap& b = test::builtMap();
  const std::string path = test::scratchDir("mapfile_atomic") + "/map.plmap";
  saveMap(path, Map(), b.camera, "old");
  saveMap(path, *b.map, b.camera, b.config_yaml);
  EXPECT_EQ(test::readFile(path), mapBytes());
  EXPECT_THROW(saveMap(test::scratchDir("mapfile_atomic2") + "/no/such/folder/map.plmap", *b.map, b.camera, ""), IoError);
}

// What the fuzzer does, briefly and deterministically: random damage inside sections whose
// CRCs are then made valid again (so the decoder, not the CRC, must catch it), and random
// truncations and byte flips of the whole file. Each must give a map or a plslam::Error.
TEST(MapFile, DamagedContentNeverCrashes) {
  const test::BuiltMap& b = test::builtMap();
  // A small map keeps this fast: the first keyframes of the shared one with their landmarks.
  Map small;
  {
    const LoadedMap l = parseMap(mapBytes(), kName);
    std::set<Id> keep;
    for (const auto& [id, kf] : l.map.keyframes())
      if (keep.size() < 2) keep.insert(id);
    for (const auto& [id, kf] : l.map.keyframes()) {
      if (!keep.count(id)) continue;
      KeyFrame k = kf;
      k.features.points.resize(40);
      k.features.point_descriptors = k.features.point_descriptors.rowRange(0, 40).clone();
      k.point_ids.assign(40, kNoId);
      k.line_ids.assign(k.line_ids.size(), kNoId);
      k.dense.resize(std::min<size_t>(k.dense.size(), 30));
      small.restoreKeyFrame(k);
    }
    int n = 0;
    for (const auto& [id, p] : l.map.points()) {
      if (n++ > 30) break;
      MapPoint q = p;
      q.observations.clear();
      small.restorePoint(q);
      for (Id kf : keep) small.addPointObservation(kf, n, id);
    }
  }
  const std::string good = serializeMap(small, b.camera, "system.sequential: true\n");
  ASSERT_NO_THROW(parseMap(good, kName));
  ASSERT_LT(good.size(), 200000u) << "keep the damaged files small: this test parses thousands";
  const mapfile::Container base = mapfile::unpackContainer(good, kName);
  std::mt19937 rng(12345);
  int accepted = 0, refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    mapfile::Container c = base;
    mapfile::Section& s = c.sections[rng() % c.sections.size()];
    const int kind = trial % 4;
    if (kind == 0 && !s.bytes.empty()) {
      for (int k = 0; k < 1 + static_cast<int>(rng() % 4); ++k) s.bytes[rng() % s.bytes.size()] = static_cast<char>(rng());
    } else if (kind == 1) {
      s.bytes.resize(s.bytes.empty() ? 0 : rng() % s.bytes.size());
    } else if (kind == 2 && s.bytes.size() >= 4) {
      const size_t at = rng() % (s.bytes.size() - 3);  // a big count or size somewhere
      const uint32_t v = rng() % 2 ? 0xffffffffu : 0x7fffffffu - (rng() % 1000);
      for (int i = 0; i < 4; ++i) s.bytes[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
    } else {
      std::string junk(rng() % 64, '\0');
      for (char& ch : junk) ch = static_cast<char>(rng());
      s.bytes.insert(s.bytes.empty() ? 0 : rng() % s.bytes.size(), junk);
    }
    try {
      parseMap(mapfile::packContainer(c), kName);
      ++accepted;
    } catch (const Error&) {
      ++refused;
    }
  }
  for (int trial = 0; trial < 2000; ++trial) {
    std::string bytes = good;
    if (trial % 2) bytes.resize(rng() % bytes.size());
    else bytes[rng() % bytes.size()] ^= static_cast<char>(1 + rng() % 255);
    try {
      parseMap(bytes, kName);
      ++accepted;
    } catch (const Error&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 3000) << "most damage must be refused";
  std::printf("damaged maps: %d refused, %d accepted (damage in unchecked values such as positions)\n", refused, accepted);
}

TEST(MapFile, MapFrameSectionRoundTripsAndOlderFilesLoadWithoutIt) {
  const test::BuiltMap& b = test::builtMap();
  MapFrame f;
  f.T_map_world = SE3(Eigen::Quaterniond(Eigen::AngleAxisd(1.7, Eigen::Vector3d(1, 0.2, 0).normalized())),
                      Eigen::Vector3d(0, 0.1, 1.3));
  f.floor_method = "ransac";
  f.floor_source = "dense";
  const LoadedMap with = parseMap(serializeMap(Map(), b.camera, "x", &f), "with.plmap");
  ASSERT_TRUE(with.frame.has_value());
  EXPECT_LT((with.frame->T_map_world.inverse() * f.T_map_world).angle(), 1e-8);
  EXPECT_LT((with.frame->T_map_world.translation() - f.T_map_world.translation()).norm(), 1e-8);
  EXPECT_EQ(with.frame->floor_method, "ransac");
  // A file without the section (as written before it existed) loads, with no frame.
  const std::string older = serializeMap(Map(), b.camera, "x");
  EXPECT_FALSE(parseMap(older, "older.plmap").frame.has_value());
  EXPECT_EQ(mapfile::unpackContainer(older, "older").version, mapfile::kFormatVersion) << "no version bump";
  // A damaged section (valid CRC, bad content) is refused naming it.
  mapfile::Container c = mapfile::unpackContainer(serializeMap(Map(), b.camera, "x", &f), "with");
  for (mapfile::Section& s : c.sections)
    if (s.name == "map_frame") s.bytes.replace(s.bytes.find("rotation: ["), 11, "rotation: [7, ");
  const std::string msg = refusal<IoError>(mapfile::packContainer(c));
  EXPECT_NE(msg.find("map_frame section"), std::string::npos) << msg;
}
