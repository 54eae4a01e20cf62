#include "mapfile/byte_io.h"

#include <cstring>

#include "core/error.h"

namespace plslam::mapfile {

void ByteWriter::f32(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  u32(bits);
}

void ByteWriter::f64(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  u64(bits);
}

void ByteWriter::count(size_t n) {
  if (n > 0xffffffffu) throw DataError("map file: " + std::to_string(n) + " items do not fit a 32-bit count");
  u32(static_cast<uint32_t>(n));
}

void ByteWriter::str(const std::string& s) {
  count(s.size());
  out_.append(s);
}

uint64_t ByteReader::unsignedLE(int n) {
  if (remaining() < static_cast<size_t>(n)) fail("ends in the middle of a value");
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(static_cast<unsigned char>(data_[pos_ + i])) << (8 * i);
  pos_ += n;
  return v;
}

float ByteReader::f32() {
  const uint32_t bits = u32();
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

double ByteReader::f64() {
  const uint64_t bits = u64();
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

size_t ByteReader::count(size_t min_item_bytes, const char* what) {
  const size_t n = u32();
  if (min_item_bytes > 0 && n > remaining() / min_item_bytes)
    fail(std::string("claims ") + std::to_string(n) + " " + what + " but only " + std::to_string(remaining()) +
         " bytes remain");
  return n;
}

std::string ByteReader::str(const char* what) {
  const size_t n = count(1, what);
  std::string s(data_ + pos_, n);
  pos_ += n;
  return s;
}

void ByteReader::bytes(void* out, size_t size, const char* what) {
  if (size > remaining())
    fail(std::string("needs ") + std::to_string(size) + " bytes of " + what + ", " + std::to_string(remaining()) +
         " remain");
  if (size) std::memcpy(out, data_ + pos_, size);
  pos_ += size;
}

void ByteReader::expectEnd() {
  if (remaining() != 0) fail(std::to_string(remaining()) + " unread bytes at its end");
}

void ByteReader::fail(const std::string& problem) const {
  throw IoError(file_ + ": section '" + section_ + "' is malformed at byte " + std::to_string(pos_) + ": " + problem);
}

}  // namespace plslam::mapfile
