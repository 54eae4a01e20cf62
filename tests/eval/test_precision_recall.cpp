// Precision-recall sweeps on hand-made proposal lists with known answers.
#include <gtest/gtest.h>

#include "eval/precision_recall.h"

using namespace plslam;

TEST(PrecisionRecall, SweepCountsKeptProposalsAndStopsRecallAtTheFirstFalsePositive) {
  // Scores 0.9 (right), 0.8 (right), 0.7 (wrong), 0.6 (right); 5 queries have a true answer.
  const std::vector<ScoredProposal> p{{0.6, true}, {0.9, true}, {0.7, false}, {0.8, true}};
  const PrCurve c = precisionRecall(p, 5);
  ASSERT_EQ(c.points.size(), 4u);
  EXPECT_DOUBLE_EQ(c.points[0].threshold, 0.9);
  EXPECT_DOUBLE_EQ(c.points[1].recall, 0.4);
  EXPECT_DOUBLE_EQ(c.points[2].precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(c.points[3].precision, 0.75);
  EXPECT_DOUBLE_EQ(c.points[3].recall, 0.6);
  EXPECT_DOUBLE_EQ(c.recall_at_precision_1, 0.4);
}

TEST(PrecisionRecall, TiedScoresAreKeptOrDroppedTogether) {
  const PrCurve c = precisionRecall({{0.5, true}, {0.5, false}, {0.4, true}}, 2);
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_DOUBLE_EQ(c.points[0].precision, 0.5);
  EXPECT_DOUBLE_EQ(c.recall_at_precision_1, 0.0) << "the tie holds a false positive";
}

TEST(PrecisionRecall, OperatingPointKeepsScoresAtTheThreshold) {
  const std::vector<ScoredProposal> p{{0.9, true}, {0.7, false}, {0.6, true}, {0.5, true}};
  const PrPoint at = operatingPoint(p, 4, 0.6);
  EXPECT_EQ(at.true_positives, 2);
  EXPECT_EQ(at.false_positives, 1);
  EXPECT_DOUBLE_EQ(at.precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(at.recall, 0.5);
  EXPECT_DOUBLE_EQ(operatingPoint(p, 4, 0.95).precision, 1.0) << "nothing kept";
}

TEST(PrecisionRecall, MarginSaysWhetherOneCurveIsAtLeastAsGoodEverywhere) {
  const PrCurve better = precisionRecall({{0.9, true}, {0.8, true}, {0.7, false}, {0.6, true}}, 4);
  const PrCurve worse = precisionRecall({{0.9, true}, {0.8, false}, {0.7, true}, {0.6, true}}, 4);
  EXPECT_GE(minPrecisionMargin(better, worse), 0.0) << "equal at recall 0.25, better beyond";
  EXPECT_LT(minPrecisionMargin(worse, better), 0.0);
  EXPECT_DOUBLE_EQ(minPrecisionMargin(better, better), 0.0);
  // A curve that stops short of the other's recall is worse there.
  const PrCurve shorter = precisionRecall({{0.9, true}}, 4);
  EXPECT_LT(minPrecisionMargin(shorter, better), 0.0);
}
