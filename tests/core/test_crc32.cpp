#include "core/crc32.h"

#include <gtest/gtest.h>

#include <string>

namespace plslam {

// The standard check value of CRC-32/ISO-HDLC (the zlib/PNG CRC): the map and vocabulary
// files written before zlib computed it must still verify.
TEST(Crc32, CheckValueOfTheZlibCrc) {
  EXPECT_EQ(crc32(std::string("123456789")), 0xCBF43926u);
  EXPECT_EQ(crc32(std::string()), 0u);
}

}  // namespace plslam
