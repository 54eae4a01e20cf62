#include <gtest/gtest.h>

#include <random>
#include <set>

#include "core/id_set.h"

namespace plslam {
namespace {

TEST(IdSet, InsertTellsNewIdsFromRepeatsLikeAStdSet) {
  // Consecutive ids (as the map hands them out), repeats and far-apart ids, enough to grow
  // the table several times.
  std::mt19937 rng(7);
  std::uniform_int_distribution<Id> near(0, 3000), far(0, Id(1) << 40);
  IdSet set;
  std::set<Id> reference;
  for (int k = 0; k < 20000; ++k) {
    const Id id = k % 3 == 2 ? far(rng) : near(rng);
    EXPECT_EQ(set.insert(id), reference.insert(id).second) << "id " << id;
  }
  EXPECT_EQ(set.size(), reference.size());
  for (Id id = 0; id <= 3000; ++id) EXPECT_EQ(set.contains(id), reference.count(id) == 1) << "id " << id;
}

TEST(IdSet, ClearEmptiesTheSetForTheNextUse) {
  IdSet set;
  for (Id id = 0; id < 500; ++id) set.insert(id);
  set.clear(10);
  EXPECT_EQ(set.size(), 0u);
  for (Id id = 0; id < 500; ++id) EXPECT_FALSE(set.contains(id));
  EXPECT_TRUE(set.insert(42));
  EXPECT_TRUE(set.contains(42));
}

TEST(IdSet, NoIdIsNeverAMember) {
  IdSet set;
  EXPECT_FALSE(set.contains(kNoId));
  EXPECT_FALSE(set.insert(kNoId));
  EXPECT_FALSE(set.contains(kNoId));
  EXPECT_EQ(set.size(), 0u);
}

}  // namespace
}  // namespace plslam
