// The inverted-index keyframe database: DBoW2 L1 scores on known vectors, add / remove.
#include <gtest/gtest.h>

#include "place/keyframe_database.h"

using namespace plslam;

TEST(KeyframeDatabase, ScoresEqualTheL1ScoreAndOnlySharingKeyframesAreReturned) {
  KeyframeDatabase db;
  const BowVector a{{1, 0.5f}, {2, 0.5f}}, b{{2, 0.25f}, {3, 0.75f}}, c{{7, 1.0f}};
  db.add(10, {a, {{5, 1.0f}}});
  db.add(11, {b, {}});
  db.add(12, {c, {}});
  const std::vector<DatabaseScore> r = db.query({{{1, 0.5f}, {2, 0.5f}}, {{5, 1.0f}}});
  ASSERT_EQ(r.size(), 2u) << "keyframe 12 shares no word";
  EXPECT_EQ(r[0].keyframe, 10);
  EXPECT_NEAR(r[0].orb, 1.0, 1e-6);
  EXPECT_NEAR(r[0].lbd, 1.0, 1e-6);
  EXPECT_EQ(r[0].shared_words, 3);
  EXPECT_EQ(r[1].keyframe, 11);
  // Common word 2: 0.5 * (0.5 + 0.25 - 0.25) = 0.25 = 1 - 0.5 * |a - b|_1.
  EXPECT_NEAR(r[1].orb, 0.25, 1e-6);
  EXPECT_NEAR(r[1].orb, bowScore(a, b), 1e-6);
  EXPECT_EQ(r[1].lbd, 0.0);
}

TEST(KeyframeDatabase, RemovedAndReplacedKeyframesAreForgotten) {
  KeyframeDatabase db;
  db.add(1, {{{4, 1.0f}}, {}});
  db.add(2, {{{4, 0.5f}, {6, 0.5f}}, {}});
  EXPECT_EQ(db.size(), 2u);
  db.remove(1);
  db.remove(99);  // unknown: ignored
  std::vector<DatabaseScore> r = db.query({{{4, 1.0f}}, {}});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].keyframe, 2);
  EXPECT_NEAR(r[0].orb, 0.5, 1e-6);
  db.add(2, {{{8, 1.0f}}, {}});  // replaced: word 4 is gone
  EXPECT_TRUE(db.query({{{4, 1.0f}}, {}}).empty());
  EXPECT_FALSE(db.contains(1));
  EXPECT_TRUE(db.contains(2));
}
