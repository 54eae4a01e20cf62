#include <gtest/gtest.h>

#include "core/time.h"

using namespace plslam;

TEST(Time, ParsesTumStampExactly) {
  TimeNs t = 0;
  ASSERT_TRUE(parseSecondsStamp("1305031102.175304", &t));
  EXPECT_EQ(t, 1305031102175304000LL);
  EXPECT_EQ(formatSecondsStamp(t), "1305031102.175304");
  ASSERT_TRUE(parseSecondsStamp("12", &t));
  EXPECT_EQ(t, 12 * kNsPerSecond);
}

TEST(Time, RejectsNonNumbers) {
  TimeNs t = 0;
  EXPECT_FALSE(parseSecondsStamp("", &t));
  EXPECT_FALSE(parseSecondsStamp("abc", &t));
  EXPECT_FALSE(parseSecondsStamp("1.2.3", &t));
  EXPECT_FALSE(parseSecondsStamp("-5", &t));
  EXPECT_FALSE(parseSecondsStamp("nan", &t));
  EXPECT_FALSE(parseSecondsStamp("99999999999999999999", &t));
}
