#include <gtest/gtest.h>

#include <cstdlib>

#include "io/associate.h"
#include "io/tum_line.h"

using namespace plslam;

namespace {
TimeNs ms(int64_t milliseconds) { return milliseconds * 1'000'000LL; }
}  // namespace

TEST(Associate, PairsOnlyStampsCloserThanMaxDifference) {
  // 0.03 s apart is outside the 0.02 s window; 0.01 s apart is inside.
  const std::vector<TimeNs> a = {ms(1000), ms(2000)};
  const std::vector<TimeNs> b = {ms(1030), ms(2010)};
  const auto m = associateStamps(a, b, 0.02);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].first, 1u);
  EXPECT_EQ(m[0].second, 1u);
}

TEST(Associate, GreedySmallestDifferenceFirstEachStampOnce) {
  // a1-b0 (0.001) is taken first; a0-b0 (0.009) then has no partner left, and a1-b1 (0.015)
  // neither: a nearest-neighbour pass from the first list would have paired both.
  const std::vector<TimeNs> a = {ms(0), ms(10)};
  const std::vector<TimeNs> b = {ms(9), ms(25)};
  const auto m = associateStamps(a, b, 0.02);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].first, 1u);
  EXPECT_EQ(m[0].second, 0u);
}

TEST(Associate, ResultSortedByFirstStampWhateverTheInputOrder) {
  const std::vector<TimeNs> a = {ms(3000), ms(1000), ms(2000)};
  const std::vector<TimeNs> b = {ms(1001), ms(2002), ms(3003)};
  const auto m = associateStamps(a, b, 0.02);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(a[m[0].first], ms(1000));
  EXPECT_EQ(b[m[0].second], ms(1001));
  EXPECT_EQ(a[m[1].first], ms(2000));
  EXPECT_EQ(a[m[2].first], ms(3000));
  EXPECT_EQ(b[m[2].second], ms(3003));
}

TEST(Associate, OffsetShiftsTheSecondList) {
  const std::vector<TimeNs> a = {ms(1000)};
  const std::vector<TimeNs> b = {ms(1500)};
  EXPECT_TRUE(associateStamps(a, b, 0.02).empty());
  EXPECT_EQ(associateStamps(a, b, 0.02, -0.5).size(), 1u);
}

TEST(Associate, StampSecondsIsTheNearestDoubleToTheDecimal) {
  EXPECT_EQ(stampSeconds(1305031102175304000LL), std::strtod("1305031102.175304", nullptr));
  EXPECT_EQ(stampSeconds(1311868163869700000LL), std::strtod("1311868163.8697", nullptr));
  EXPECT_EQ(stampSeconds(0), 0.0);
}

TEST(Associate, FindClosestIndexFindsTheNearestElement) {
  const std::vector<double> s = {1.0, 2.0, 3.0, 10.0};
  EXPECT_EQ(findClosestIndex(s, -5.0), 0u);
  EXPECT_EQ(findClosestIndex(s, 2.4), 1u);
  EXPECT_EQ(findClosestIndex(s, 2.6), 2u);
  EXPECT_EQ(findClosestIndex(s, 3.0), 2u);
  EXPECT_EQ(findClosestIndex(s, 7.0), 3u);
  EXPECT_EQ(findClosestIndex(s, 100.0), 3u);
}

// Found by fuzzing: a line of vertical tabs / form feeds passed the blank-line check but
// produced no field, and the list reader then read past an empty vector.
TEST(TumLine, ALineOfOtherWhitespaceIsBlank) {
  std::vector<std::string> f{"stale"};
  EXPECT_FALSE(splitTumLine("\v\f \v", &f));
  EXPECT_TRUE(f.empty());
  EXPECT_TRUE(splitTumLine("1.0\vrgb/1.png", &f));
  EXPECT_EQ(f.size(), 2u);
}
