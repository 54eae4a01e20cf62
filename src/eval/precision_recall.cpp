#include "eval/precision_recall.h"

#include <algorithm>

namespace plslam {

PrCurve precisionRecall(const std::vector<ScoredProposal>& proposals, int positives) {
  std::vector<ScoredProposal> sorted = proposals;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const ScoredProposal& a, const ScoredProposal& b) { return a.score > b.score; });
  PrCurve c;
  int tp = 0, fp = 0;
  for (size_t k = 0; k < sorted.size(); ++k) {
    (sorted[k].correct ? tp : fp) += 1;
    if (k + 1 < sorted.size() && sorted[k + 1].score == sorted[k].score) continue;
    PrPoint p;
    p.threshold = sorted[k].score;
    p.true_positives = tp;
    p.false_positives = fp;
    p.precision = static_cast<double>(tp) / (tp + fp);
    p.recall = positives > 0 ? static_cast<double>(tp) / positives : 0.0;
    if (fp == 0) c.recall_at_precision_1 = p.recall;
    c.points.push_back(p);
  }
  return c;
}

PrPoint operatingPoint(const std::vector<ScoredProposal>& proposals, int positives, double threshold) {
  PrPoint p;
  p.threshold = threshold;
  for (const ScoredProposal& s : proposals) {
    if (s.score < threshold) continue;
    (s.correct ? p.true_positives : p.false_positives) += 1;
  }
  const int kept = p.true_positives + p.false_positives;
  p.precision = kept > 0 ? static_cast<double>(p.true_positives) / kept : 1.0;
  p.recall = positives > 0 ? static_cast<double>(p.true_positives) / positives : 0.0;
  return p;
}

namespace {
double interpolatedPrecision(const PrCurve& c, double recall) {
  double best = 0;
  for (const PrPoint& p : c.points)
    if (p.recall >= recall) best = std::max(best, p.precision);
  return best;
}
}  // namespace

double minPrecisionMargin(const PrCurve& a, const PrCurve& b) {
  double margin = 0;
  bool any = false;
  for (const PrPoint& p : b.points) {
    const double d = interpolatedPrecision(a, p.recall) - interpolatedPrecision(b, p.recall);
    margin = any ? std::min(margin, d) : d;
    any = true;
  }
  return margin;
}

}  // namespace plslam
