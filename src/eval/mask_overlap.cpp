#include "eval/mask_overlap.h"

#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {
double ratio(int64_t part, int64_t whole) { return whole == 0 ? 1.0 : static_cast<double>(part) / static_cast<double>(whole); }
}  // namespace

void MaskOverlap::add(const cv::Mat& predicted, const cv::Mat& truth) {
  if (truth.channels() != 1 || (!predicted.empty() && (predicted.channels() != 1 || predicted.size() != truth.size())))
    throw DataError(str("mask overlap: masks of ", predicted.cols, "x", predicted.rows, "x", predicted.channels(), " and ",
                        truth.cols, "x", truth.rows, "x", truth.channels(), " cannot be compared"));
  const cv::Mat is_true = truth != 0;
  const cv::Mat is_predicted = predicted.empty() ? cv::Mat::zeros(truth.size(), CV_8U) : cv::Mat(predicted != 0);
  const int both = cv::countNonZero(is_true & is_predicted);
  true_positive += both;
  false_positive += cv::countNonZero(is_predicted) - both;
  false_negative += cv::countNonZero(is_true) - both;
}

double MaskOverlap::precision() const { return ratio(true_positive, true_positive + false_positive); }
double MaskOverlap::recall() const { return ratio(true_positive, true_positive + false_negative); }
double MaskOverlap::iou() const { return ratio(true_positive, true_positive + false_positive + false_negative); }

}  // namespace plslam
