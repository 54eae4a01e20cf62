// The map file's container: a magic, the format version, a small text header (what wrote
// the file, the entity counts and the section table: name, byte length and CRC-32 of each
// section) with its own CRC-32, then the sections back to back in table order.
//
//   offset 0    8 bytes   magic "PLSLAMAP"
//          8    u32       format version (little-endian, like every number in the file)
//         12    u32       header length H
//         16    H bytes   header text, ASCII lines "key: value" (see packContainer)
//     16 + H    u32       CRC-32 of bytes [0, 16 + H)
//     20 + H    ...       the sections
//
// Readers of format version N refuse files of any other version with a message saying both.
// Unknown header keys and unknown sections are skipped (after their CRC was checked), so
// additive fields can come as new sections without a version bump.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace plslam::mapfile {

constexpr char kMagic[9] = "PLSLAMAP";
constexpr uint32_t kFormatVersion = 1;
/// Upper bound of the header text: far above any real header, it keeps a corrupt length
/// field from reading megabytes as text.
constexpr uint32_t kMaxHeaderBytes = 1 << 20;

struct Section {
  std::string name;   ///< [a-z_]+, unique in a file
  std::string bytes;  ///< the section's content
};

struct Container {
  uint32_t version = kFormatVersion;
  std::string writer = "plslam mapfile";  ///< what wrote the file (for people)
  int64_t keyframes = 0, points = 0, lines = 0;  ///< entity counts (for people; the loader cross-checks them)
  std::vector<Section> sections;

  /// The section called `name`, or nullptr.
  const Section* find(const std::string& name) const;
};

/// The file's bytes.
std::string packContainer(const Container& c);
/// Checks magic, version, header CRC, the header, each section's presence (truncation) and
/// CRC. Throws IoError "<name_for_messages>: ..." saying which check failed and where.
Container unpackContainer(const std::string& bytes, const std::string& name_for_messages);

}  // namespace plslam::mapfile
