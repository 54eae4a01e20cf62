// Precision-recall of a detector that proposes one answer per query with a score: sweeping
// a threshold on the score gives precision (correct proposals / proposals kept) and recall
// (correct proposals kept / queries that have a correct answer). Used by `plslam eval loops`.
#pragma once

#include <vector>

namespace plslam {

struct ScoredProposal {
  double score = 0;
  bool correct = false;  ///< the proposal is a true answer
};

struct PrPoint {
  double threshold = 0;  ///< proposals with score >= threshold are kept
  double precision = 1;  ///< 1 when nothing is kept
  double recall = 0;
  int true_positives = 0, false_positives = 0;
};

struct PrCurve {
  std::vector<PrPoint> points;       ///< one per distinct score, from the highest threshold down
  double recall_at_precision_1 = 0;  ///< the largest recall before the first false positive
};

/// The curve over every distinct score (ties are kept or dropped together).
PrCurve precisionRecall(const std::vector<ScoredProposal>& proposals, int positives);

/// The point at one threshold.
PrPoint operatingPoint(const std::vector<ScoredProposal>& proposals, int positives, double threshold);

/// How much better `a` is than `b` where it is worst: the minimum, over the recalls that `b`
/// reaches, of a's interpolated precision minus b's (interpolated precision at recall r: the
/// best precision at any recall >= r; 0 where the curve does not reach r). >= 0 means `a` is
/// at least as good as `b` everywhere on the curve.
double minPrecisionMargin(const PrCurve& a, const PrCurve& b);

}  // namespace plslam
