// Explicit little-endian encoding of the map file's fields, independent of the host's byte
// order and of struct padding. The reader bounds every read (and every count, before
// anything is allocated) by the bytes that remain, so no byte string can make it read out
// of range or allocate more than the input could describe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace plslam::mapfile {

class ByteWriter {
 public:
  void u8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u16(uint16_t v) { unsignedLE(v, 2); }
  void u32(uint32_t v) { unsignedLE(v, 4); }
  void u64(uint64_t v) { unsignedLE(v, 8); }
  void i16(int16_t v) { u16(static_cast<uint16_t>(v)); }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void i64(int64_t v) { u64(static_cast<uint64_t>(v)); }
  void f32(float v);
  void f64(double v);
  /// A count or length, as u32 (throws DataError above 2^32 - 1).
  void count(size_t n);
  /// u32 length, then the bytes.
  void str(const std::string& s);
  void bytes(const void* data, size_t size) { out_.append(static_cast<const char*>(data), size); }
  const std::string& data() const { return out_; }
  std::string take() { return std::move(out_); }

 private:
  void unsignedLE(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  std::string out_;
};

/// Reads one section. Errors throw IoError "<file>: section '<section>' is malformed: ...".
class ByteReader {
 public:
  ByteReader(const char* data, size_t size, std::string file, std::string section)
      : data_(data), size_(size), file_(std::move(file)), section_(std::move(section)) {}

  uint8_t u8() { return static_cast<uint8_t>(unsignedLE(1)); }
  uint16_t u16() { return static_cast<uint16_t>(unsignedLE(2)); }
  uint32_t u32() { return static_cast<uint32_t>(unsignedLE(4)); }
  uint64_t u64() { return unsignedLE(8); }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  int64_t i64() { return static_cast<int64_t>(u64()); }
  float f32();
  double f64();
  /// A u32 count of items that take at least `min_item_bytes` each; fails when the rest of
  /// the section is too short to hold them (so it is safe to reserve/allocate that many).
  size_t count(size_t min_item_bytes, const char* what);
  std::string str(const char* what);
  /// Copies `size` bytes (checked against what remains).
  void bytes(void* out, size_t size, const char* what);

  size_t remaining() const { return size_ - pos_; }
  size_t position() const { return pos_; }
  /// Throws unless the whole section was read.
  void expectEnd();
  /// IoError naming the file, the section and the offset in it.
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  uint64_t unsignedLE(int n);
  const char* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string file_, section_;
};

}  // namespace plslam::mapfile
