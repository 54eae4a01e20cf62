// Matching through the vocabulary's nodes and the tracker's place index.
#include <gtest/gtest.h>

#include <random>

#include "place/keyframe_places.h"
#include "place/vocabulary_matching.h"

using namespace plslam;

namespace {

// Random 32-byte descriptors (one per row) and copies with `flips` bits flipped each.
cv::Mat randomDescriptors(int rows, std::mt19937* rng) {
  cv::Mat d(rows, 32, CV_8U);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 32; ++c) d.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(*rng));
  return d;
}
cv::Mat flipped(const cv::Mat& d, int flips, std::mt19937* rng) {
  cv::Mat out = d.clone();
  std::uniform_int_distribution<int> bit(0, 255);
  for (int r = 0; r < out.rows; ++r)
    for (int f = 0; f < flips; ++f) {
      const int b = bit(*rng);
      out.at<uint8_t>(r, b / 8) ^= static_cast<uint8_t>(1 << (b % 8));
    }
  return out;
}

// A vocabulary trained on the descriptors themselves (3 levels of 4), both trees alike.
std::shared_ptr<const VocabularySet> vocabularyOf(const std::vector<cv::Mat>& images) {
  VocabularyTrainOptions o;
  o.k = 4;
  o.levels = 3;
  auto v = std::make_shared<VocabularySet>();
  v->orb = Vocabulary::train(images, o);
  v->lbd = v->orb;
  return v;
}

FrameFeatures featuresOf(const cv::Mat& descriptors) {
  FrameFeatures f;
  f.point_descriptors = descriptors;
  f.points.resize(descriptors.rows);
  return f;
}

}  // namespace

TEST(VocabularyNodes, TheNodeAtADepthIsSharedByDescriptorsOfTheSameWord) {
  std::mt19937 rng(1);
  const cv::Mat d = randomDescriptors(400, &rng);
  const auto v = vocabularyOf({d});
  std::map<int, std::set<int>> nodes_of_word;
  for (int r = 0; r < d.rows; ++r) {
    int node = -1;
    const int w = v->orb.word(d.ptr<uint8_t>(r), kMatchingNodeDepth, &node);
    ASSERT_GE(node, 0);
    nodes_of_word[w].insert(node);
  }
  for (const auto& [w, nodes] : nodes_of_word) EXPECT_EQ(nodes.size(), 1u) << "word " << w;
  // Fewer groups than words: the node is an ancestor, not the leaf.
  std::set<int> all;
  for (int n : matchingNodes(v->orb, d)) all.insert(n);
  EXPECT_LT(all.size(), nodes_of_word.size());
  EXPECT_LE(all.size(), 16u);  // 4^2 nodes at depth 2
}

TEST(MatchByVocabulary, PairsNoisyCopiesWithTheirOriginalsAndNothingElse) {
  std::mt19937 rng(2);
  const cv::Mat train = randomDescriptors(300, &rng);
  const cv::Mat query = flipped(train, 6, &rng);
  const auto v = vocabularyOf({train});
  const std::vector<int> tn = matchingNodes(v->orb, train), qn = matchingNodes(v->orb, query);
  const auto matches = matchByVocabulary(query, qn, train, tn, BruteForceOptions{64, 0.8f, true});
  int same_node = 0;
  for (int r = 0; r < query.rows; ++r) same_node += qn[r] == tn[r];
  ASSERT_GT(same_node, 250);  // 6 flipped bits rarely change the branch
  EXPECT_EQ(static_cast<int>(matches.size()), same_node);
  for (const DescriptorMatch& m : matches) {
    EXPECT_EQ(m.query, m.train);
    EXPECT_LE(m.distance, 6);
  }
}

TEST(MatchByVocabulary, RowsWithoutANodeAreSkipped) {
  std::mt19937 rng(3);
  const cv::Mat train = randomDescriptors(100, &rng);
  const auto v = vocabularyOf({train});
  const std::vector<int> nodes = matchingNodes(v->orb, train);
  std::vector<int> query_nodes = nodes;
  for (int r = 0; r < 100; r += 2) query_nodes[r] = -1;
  const auto matches = matchByVocabulary(train, query_nodes, train, nodes, BruteForceOptions{64, 0.8f, true});
  EXPECT_EQ(matches.size(), 50u);
  for (const DescriptorMatch& m : matches) EXPECT_EQ(m.query % 2, 1);
}

TEST(KeyframePlaces, TheKeyframeWithTheSameFeaturesRanksFirstAndTheListIsCut) {
  std::mt19937 rng(4);
  // Each keyframe: noisy copies of its own 8 descriptors, so each holds few of the 64 words.
  std::vector<cv::Mat> keyframes;
  for (int k = 0; k < 6; ++k) {
    const cv::Mat own = randomDescriptors(8, &rng);
    cv::Mat copies;
    for (int c = 0; c < 20; ++c) copies.push_back(flipped(own, 4, &rng));
    keyframes.push_back(copies);
  }
  KeyframePlaces places(vocabularyOf(keyframes));
  ASSERT_TRUE(places.enabled());
  for (int k = 0; k < 6; ++k) places.add(10 + k, featuresOf(keyframes[k]));
  EXPECT_EQ(places.size(), 6u);
  PlaceQueryOptions o;
  o.max_candidates = 3;
  o.min_relative_score = 0.0;
  const auto found = places.query(places.describe(featuresOf(flipped(keyframes[4], 4, &rng))), o);
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0].keyframe, 14);
  EXPECT_GT(found[0].score, 2 * found[1].score);
  o.min_relative_score = 0.9;  // only keyframes almost as similar as the best
  EXPECT_EQ(places.query(places.describe(featuresOf(keyframes[4])), o).size(), 1u);
}

TEST(KeyframePlaces, WithoutAVocabularyNothingIsIndexed) {
  KeyframePlaces places(nullptr);
  EXPECT_FALSE(places.enabled());
  std::mt19937 rng(5);
  places.add(1, featuresOf(randomDescriptors(10, &rng)));
  EXPECT_EQ(places.size(), 0u);
  EXPECT_EQ(places.words(1), nullptr);
}
