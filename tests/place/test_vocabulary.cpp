// Vocabulary training (k-majority tree), tf-idf vectors, L1 scores and the file format.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "core/error.h"
#include "place/vocabulary.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

// `clusters` random 32-byte centres; each image holds a few noisy copies (a few bits
// flipped) of some of them.
struct ClusteredData {
  std::vector<cv::Mat> centres;  // one row each
  std::vector<cv::Mat> images;
};

cv::Mat noisyCopy(const cv::Mat& centre, int flips, std::mt19937& rng) {
  cv::Mat d = centre.clone();
  for (int f = 0; f < flips; ++f) {
    const int bit = static_cast<int>(rng() % 256);
    d.at<uint8_t>(0, bit / 8) ^= static_cast<uint8_t>(1u << (bit % 8));
  }
  return d;
}

ClusteredData makeData(int clusters, int images, uint32_t seed) {
  std::mt19937 rng(seed);
  ClusteredData data;
  for (int c = 0; c < clusters; ++c) {
    cv::Mat m(1, 32, CV_8U);
    for (int b = 0; b < 32; ++b) m.at<uint8_t>(0, b) = static_cast<uint8_t>(rng());
    data.centres.push_back(m);
  }
  for (int i = 0; i < images; ++i) {
    cv::Mat img;
    for (int c = 0; c < clusters; ++c)
      if ((rng() % 3) == 0)
        for (int k = 0; k < 4; ++k) img.push_back(noisyCopy(data.centres[c], 6, rng));
    data.images.push_back(img);
  }
  return data;
}

double l1(const BowVector& v) {
  double s = 0;
  for (const auto& [w, x] : v) s += std::fabs(x);
  return s;
}

}  // namespace

TEST(Vocabulary, NoisyCopiesOfACentreFallIntoItsWordAndWordsAreBounded) {
  const ClusteredData data = makeData(60, 40, 3);
  VocabularyTrainOptions o;
  o.k = 4;
  o.levels = 4;
  const Vocabulary v = Vocabulary::train(data.images, o);
  EXPECT_GT(v.words(), 30);
  EXPECT_LE(v.words(), 4 * 4 * 4 * 4);
  std::mt19937 rng(99);
  int same = 0, total = 0;
  for (const cv::Mat& c : data.centres) {
    const int w = v.word(c.ptr<uint8_t>());
    for (int k = 0; k < 5; ++k, ++total) same += v.word(noisyCopy(c, 4, rng).ptr<uint8_t>()) == w;
  }
  EXPECT_GT(same, 0.9 * total) << "descriptors a few bits apart should share their word";
}

TEST(Vocabulary, TransformIsL1NormalisedAndScoresBehave) {
  const ClusteredData data = makeData(60, 40, 4);
  const Vocabulary v = Vocabulary::train(data.images, {});
  const BowVector a = v.transform(data.images[0]);
  const BowVector b = v.transform(data.images[1]);
  ASSERT_FALSE(a.empty());
  EXPECT_NEAR(l1(a), 1.0, 1e-5);
  for (size_t i = 1; i < a.size(); ++i) EXPECT_LT(a[i - 1].first, a[i].first) << "sorted by word";
  EXPECT_NEAR(bowScore(a, a), 1.0, 1e-5);
  EXPECT_NEAR(bowScore(a, b), bowScore(b, a), 1e-9);
  EXPECT_LT(bowScore(a, b), 0.9);
  EXPECT_EQ(bowScore(a, {}), 0.0);
  // Disjoint words score 0; identical up to scale score 1.
  EXPECT_DOUBLE_EQ(bowScore({{1, 0.5f}, {3, 0.5f}}, {{2, 0.5f}, {4, 0.5f}}), 0.0);
  EXPECT_NEAR(bowScore({{1, 0.25f}, {3, 0.75f}}, {{1, 0.75f}, {3, 0.25f}}), 0.5, 1e-6);
}

TEST(Vocabulary, TrainingIsDeterministicAndBadOptionsAreRefused) {
  const ClusteredData data = makeData(30, 20, 5);
  EXPECT_TRUE(Vocabulary::train(data.images, {}) == Vocabulary::train(data.images, {}));
  VocabularyTrainOptions bad;
  bad.k = 1;
  EXPECT_THROW(Vocabulary::train(data.images, bad), ConfigError);
  EXPECT_THROW(Vocabulary::train({cv::Mat()}, {}), DataError);
  EXPECT_THROW(Vocabulary::train({cv::Mat(3, 16, CV_8U, cv::Scalar(1))}, {}), DataError);
}

TEST(VocabularyFile, RoundTripKeepsEveryNodeAndCorruptionIsRefused) {
  const ClusteredData data = makeData(50, 30, 6);
  VocabularySet set;
  set.orb = Vocabulary::train(data.images, {});
  VocabularyTrainOptions o;
  o.k = 3;
  o.levels = 3;
  set.lbd = Vocabulary::train(data.images, o);
  const std::string path = test::scratchDir("loop_vocab") + "/v.voc";
  saveVocabulary(path, set);
  const VocabularySet back = loadVocabulary(path);
  EXPECT_TRUE(back.orb == set.orb);
  EXPECT_TRUE(back.lbd == set.lbd);
  EXPECT_EQ(back.orb.transform(data.images[2]), set.orb.transform(data.images[2]));

  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto writeAndExpect = [&](const std::string& content, const std::string& needle) {
    const std::string p = test::scratchDir("loop_vocab") + "/bad.voc";
    std::ofstream(p, std::ios::binary) << content;
    try {
      loadVocabulary(p);
      ADD_FAILURE() << "a corrupt file was accepted (" << needle << ")";
    } catch (const DataError& e) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  writeAndExpect(flipped, "CRC");
  writeAndExpect(bytes.substr(0, bytes.size() - 100), "CRC");
  std::string magic = bytes;
  magic[0] = 'X';
  writeAndExpect(magic, "magic");
  EXPECT_THROW(loadVocabulary(test::scratchDir("loop_vocab") + "/missing.voc"), IoError);
}

TEST(VocabularyFile, ShippedVocabularyLoads) {
  const VocabularySet v = loadVocabulary(defaultVocabularyPath());
  EXPECT_GT(v.orb.words(), 1000);
  EXPECT_GT(v.lbd.words(), 1000);
}
