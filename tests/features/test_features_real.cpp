// Two real TUM frames (../shared; skipped visibly when absent): the counts are sane and
// consecutive frames match.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "features/line_extractor.h"
#include "features/matching.h"
#include "features/orb_extractor.h"
#include "support/test_support.h"

namespace plslam {
namespace {

std::vector<cv::Mat> firstFrames(const std::string& dir, int n) {
  std::ifstream in(dir + "/rgb.txt");
  std::vector<cv::Mat> out;
  std::string line;
  while (static_cast<int>(out.size()) < n && std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const cv::Mat img = cv::imread(dir + "/" + line.substr(line.find(' ') + 1), cv::IMREAD_COLOR);
    if (!img.empty()) out.push_back(img);
  }
  return out;
}

TEST(FeaturesReal, TumFramesGiveSaneCountsAndMatch) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr1_xyz_0-199/rgb.txt");
  const std::vector<cv::Mat> frames = firstFrames(test::sharedDir() + "/data/tum/fr1_xyz_0-199", 2);
  ASSERT_EQ(frames.size(), 2u);
  OrbOptions oo;
  LineOptions lo;
  std::vector<std::vector<cv::KeyPoint>> kps(2);
  std::vector<cv::Mat> desc(2), ldesc(2);
  std::vector<std::vector<LineSegment2D>> lines(2);
  for (int i = 0; i < 2; ++i) {
    extractOrb(frames[i], cv::Mat(), oo, &kps[i], &desc[i]);
    EXPECT_GE(static_cast<int>(kps[i].size()), oo.num_features * 95 / 100);
    EXPECT_LE(static_cast<int>(kps[i].size()), oo.num_features);
    LineStats st;
    lines[i] = detectLines(frames[i], cv::Mat(), lo, &st);
    ldesc[i] = describeLines(frames[i], lines[i], lo);
    EXPECT_GT(st.detected, 150);
    EXPECT_GE(st.detected, st.merged);
    EXPECT_GE(st.merged, st.long_enough);
    EXPECT_GE(static_cast<int>(lines[i].size()), 40);
    EXPECT_LE(static_cast<int>(lines[i].size()), lo.max_lines);
    EXPECT_EQ(ldesc[i].rows, static_cast<int>(lines[i].size()));
  }
  // fr1_xyz moves slowly: most matches are short, consistent displacements.
  std::vector<float> a0, a1;
  for (const cv::KeyPoint& k : kps[0]) a0.push_back(k.angle);
  for (const cv::KeyPoint& k : kps[1]) a1.push_back(k.angle);
  const std::vector<DescriptorMatch> m = filterByOrientation(matchBruteForce(desc[0], desc[1], {}), a0, a1);
  EXPECT_GT(m.size(), 300u);
  int short_moves = 0;
  for (const DescriptorMatch& x : m) short_moves += cv::norm(kps[0][size_t(x.query)].pt - kps[1][size_t(x.train)].pt) < 10;
  EXPECT_GT(short_moves, 0.9 * m.size());
  BruteForceOptions lbo;
  lbo.max_distance = 80;
  const std::vector<DescriptorMatch> lm = matchBruteForce(ldesc[0], ldesc[1], lbo);
  EXPECT_GT(lm.size(), 25u);
  int close = 0;
  for (const DescriptorMatch& x : lm) {
    const LineSegment2D &s = lines[0][size_t(x.query)], &t = lines[1][size_t(x.train)];
    close += (0.5 * (s.p + s.q) - 0.5 * (t.p + t.q)).norm() < 25 && std::cos(s.angle - t.angle) > 0.98;
  }
  EXPECT_GT(close, 0.85 * lm.size()) << close << " of " << lm.size();
}

}  // namespace
}  // namespace plslam
