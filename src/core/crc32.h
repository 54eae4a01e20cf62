// CRC-32 (IEEE 802.3, the zlib/PNG one): the checksum of the map and vocabulary files.
// zlib computes it; this header only keeps zlib's types out of the callers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace plslam {

/// CRC-32 of `size` bytes.
uint32_t crc32(const void* data, size_t size);
inline uint32_t crc32(std::string_view bytes) { return crc32(bytes.data(), bytes.size()); }

}  // namespace plslam
