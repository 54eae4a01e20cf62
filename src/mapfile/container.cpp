#include "mapfile/container.h"

#include <cstdio>
#include <cstring>
#include <set>
#include <sstream>

#include "core/crc32.h"
#include "core/error.h"
#include "mapfile/byte_io.h"

namespace plslam::mapfile {

const Section* Container::find(const std::string& name) const {
  for (const Section& s : sections)
    if (s.name == name) return &s;
  return nullptr;
}

namespace {

constexpr size_t kPreambleBytes = 16;  // magic, version, header length

std::string crcHex(uint32_t crc) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "%08x", crc);
  return buf;
}

bool validName(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  for (char c : s)
    if (!((c >= 'a' && c <= 'z') || c == '_')) return false;
  return true;
}

uint32_t readU32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return v;
}

/// A non-negative decimal number (digits only, below 2^62); false otherwise.
bool parseCount(const std::string& s, int64_t* out) {
  if (s.empty() || s.size() > 18) return false;
  int64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  *out = v;
  return true;
}

bool parseHex32(const std::string& s, uint32_t* out) {
  if (s.size() != 8) return false;
  uint32_t v = 0;
  for (char c : s) {
    int d;
    if (c >= '0' && c <= '9') d = c - '0';
    else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    else return false;
    v = (v << 4) | static_cast<uint32_t>(d);
  }
  *out = v;
  return true;
}

struct TableEntry {
  std::string name;
  int64_t bytes = 0;
  uint32_t crc = 0;
};

}  // namespace

std::string packContainer(const Container& c) {
  std::ostringstream h;
  h << "plslam map\n"
    << "format: " << c.version << "\n"
    << "writer: " << c.writer << "\n"
    << "byte_order: little-endian\n"
    << "keyframes: " << c.keyframes << "\n"
    << "points: " << c.points << "\n"
    << "lines: " << c.lines << "\n"
    << "sections: " << c.sections.size() << "\n";
  std::set<std::string> names;
  for (const Section& s : c.sections) {
    if (!validName(s.name) || !names.insert(s.name).second)
      throw DataError("map file: bad or repeated section name '" + s.name + "'");
    h << "section: " << s.name << " " << s.bytes.size() << " " << crcHex(crc32(s.bytes)) << "\n";
  }
  const std::string header = h.str();
  ByteWriter w;
  w.bytes(kMagic, 8);
  w.u32(c.version);
  w.count(header.size());
  w.bytes(header.data(), header.size());
  w.u32(crc32(w.data()));
  std::string out = w.take();
  for (const Section& s : c.sections) out += s.bytes;
  return out;
}

Container unpackContainer(const std::string& b, const std::string& name) {
  auto fail = [&](const std::string& problem) -> IoError { return IoError(name + ": " + problem); };
  const size_t n_magic = std::min<size_t>(b.size(), 8);
  if (std::memcmp(b.data(), kMagic, n_magic) != 0 || b.empty())
    throw fail("not a plslam map file (bad magic: the file does not start with \"PLSLAMAP\")");
  if (b.size() < kPreambleBytes) throw fail("truncated in the preamble (" + std::to_string(b.size()) + " bytes)");
  Container c;
  c.version = readU32(b, 8);
  if (c.version != kFormatVersion)
    throw fail("map format version " + std::to_string(c.version) + (c.version > kFormatVersion ? " (newer)" : "") +
               "; this build of plslam reads version " + std::to_string(kFormatVersion));
  const uint32_t header_len = readU32(b, 12);
  if (header_len > kMaxHeaderBytes)
    throw fail("header length " + std::to_string(header_len) + " bytes is out of range (corrupt header)");
  if (b.size() < kPreambleBytes + header_len + 4)
    throw fail("truncated in the header (" + std::to_string(b.size()) + " bytes, the header ends at byte " +
               std::to_string(kPreambleBytes + header_len + 4) + ")");
  const uint32_t stored_crc = readU32(b, kPreambleBytes + header_len);
  if (crc32(b.data(), kPreambleBytes + header_len) != stored_crc) throw fail("CRC mismatch in the header (corrupt file)");

  // The header text: "key: value" lines, the first one "plslam map".
  std::istringstream text(b.substr(kPreambleBytes, header_len));
  std::string line;
  if (!std::getline(text, line) || line != "plslam map") throw fail("malformed header: first line is not \"plslam map\"");
  std::vector<TableEntry> table;
  int64_t declared_sections = -1, format = -1;
  bool have_kf = false, have_pt = false, have_ln = false;
  while (std::getline(text, line)) {
    if (line.empty()) continue;
    const size_t colon = line.find(": ");
    if (colon == std::string::npos) throw fail("malformed header line \"" + line + "\"");
    const std::string key = line.substr(0, colon), value = line.substr(colon + 2);
    auto number = [&](int64_t* out) {
      if (!parseCount(value, out)) throw fail("malformed header: " + key + " \"" + value + "\" is not a count");
    };
    if (key == "format") number(&format);
    else if (key == "writer") c.writer = value;
    else if (key == "byte_order" && value != "little-endian") throw fail("unsupported byte order \"" + value + "\"");
    else if (key == "keyframes") number(&c.keyframes), have_kf = true;
    else if (key == "points") number(&c.points), have_pt = true;
    else if (key == "lines") number(&c.lines), have_ln = true;
    else if (key == "sections") number(&declared_sections);
    else if (key == "section") {
      std::istringstream fields(value);
      TableEntry e;
      std::string bytes, crc, extra;
      if (!(fields >> e.name >> bytes >> crc) || (fields >> extra) || !validName(e.name) || !parseCount(bytes, &e.bytes) ||
          !parseHex32(crc, &e.crc))
        throw fail("malformed section entry \"" + value + "\" in the header");
      for (const TableEntry& other : table)
        if (other.name == e.name) throw fail("section '" + e.name + "' listed twice in the header");
      table.push_back(e);
    }
  }
  if (format != static_cast<int64_t>(c.version))
    throw fail("malformed header: its format line does not match the binary version " + std::to_string(c.version));
  if (!have_kf || !have_pt || !have_ln) throw fail("malformed header: keyframe, point or line count missing");
  if (declared_sections != static_cast<int64_t>(table.size()))
    throw fail("malformed header: " + std::to_string(declared_sections) + " sections declared, " +
               std::to_string(table.size()) + " listed");

  size_t at = kPreambleBytes + header_len + 4;
  for (const TableEntry& e : table) {
    const size_t left = b.size() - at;
    if (static_cast<uint64_t>(e.bytes) > left)
      throw fail("truncated in section '" + e.name + "' (" + std::to_string(left) + " of its " +
                 std::to_string(e.bytes) + " bytes present)");
    Section s{e.name, b.substr(at, static_cast<size_t>(e.bytes))};
    at += static_cast<size_t>(e.bytes);
    if (crc32(s.bytes) != e.crc) throw fail("CRC mismatch in section '" + e.name + "' (corrupt file)");
    c.sections.push_back(std::move(s));
  }
  if (at != b.size()) throw fail(std::to_string(b.size() - at) + " unexpected bytes after the last section");
  return c;
}

}  // namespace plslam::mapfile
