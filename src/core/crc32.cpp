#include "core/crc32.h"

#include <zlib.h>

namespace plslam {

uint32_t crc32(const void* data, size_t size) {
  // crc32_z takes a size_t length (zlib's crc32 only a 32-bit one).
  return static_cast<uint32_t>(::crc32_z(::crc32_z(0L, Z_NULL, 0), static_cast<const Bytef*>(data), size));
}

}  // namespace plslam
