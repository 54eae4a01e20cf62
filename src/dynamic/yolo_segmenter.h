// YOLOv8-seg instance segmentation through OpenCV DNN (CPU).
//
// Loading: the file is checked first (dynamic/onnx_check.h: present, ONNX framing), then
// read by OpenCV (a cv::Exception becomes IoError), then run once on a grey dummy input
// of the model's input size (read from the ONNX graph input, not assumed) and its outputs
// are checked against the YOLOv8-seg layout (DataError otherwise); the number of classes
// and the prototype size come from those outputs, and the class list must have as many
// names (ConfigError otherwise).
//
// Per image: letterbox (keep the aspect ratio, centre, pad with grey 114), RGB 0..1 blob,
// forward, detections whose best class score passes the confidence threshold, NMS per
// class, masks = sigmoid(coefficients x prototypes) mapped back through the letterbox to
// the image (bilinear), cut to the detection box and thresholded. Where masks overlap the
// higher-scored instance keeps the pixel.
//
// Thread safety: one thread at a time per YoloSegmenter (OpenCV's Net is not re-entrant).
// The forward pass uses OpenCV's process-wide thread pool (see YoloSegOptions::threads).
#pragma once

#include <memory>
#include <opencv2/core.hpp>

#include "dynamic/onnx_check.h"
#include "dynamic/segmenter.h"

namespace plslam {

/// The letterbox between an image and a network input: the image scaled to `resized`
/// (the same factor on both axes up to rounding to whole pixels), placed at
/// (pad_x, pad_y) in the input. Coordinates are continuous pixel coordinates (pixel i
/// spans [i, i+1), its centre is i + 0.5) in both.
struct Letterbox {
  cv::Size image;     ///< the image size
  cv::Size input;     ///< the network input size
  cv::Size resized;   ///< the scaled image inside the input
  double scale_x = 1; ///< input pixels per image pixel along x (resized.width / image.width)
  double scale_y = 1; ///< the same along y
  int pad_x = 0;      ///< left padding, input pixels
  int pad_y = 0;      ///< top padding, input pixels

  cv::Point2d imageToInput(const cv::Point2d& p) const;
  cv::Point2d inputToImage(const cv::Point2d& p) const;
  /// A box in input coordinates as whole image pixels (those it covers), clipped to the image.
  cv::Rect boxToImage(const cv::Rect2d& input_box) const;
};

/// The letterbox of `image` into `input`: the largest scale that fits, centred.
Letterbox makeLetterbox(cv::Size image, cv::Size input);

/// The image scaled and padded with 114 (every channel) to lb.input; any type.
cv::Mat applyLetterbox(const cv::Mat& image, const Letterbox& lb);

/// Samples a CV_32FC1 map that covers the whole network input (at input resolution or
/// coarser, e.g. the mask prototypes) at the centres of the image pixels of `roi`
/// (image pixels, inside the image), bilinear. Returns a CV_32FC1 of roi.size().
cv::Mat unletterboxMap(const cv::Mat& map, const Letterbox& lb, const cv::Rect& roi);

class YoloSegmenter : public Segmenter {
 public:
  /// Checks and loads the model (see above). Throws ConfigError for bad options or a class
  /// list whose size differs from the model's classes, IoError / DataError naming the file
  /// for a missing or unusable model.
  YoloSegmenter(const YoloSegOptions& options, ClassList classes);
  ~YoloSegmenter() override;
  YoloSegmenter(const YoloSegmenter&) = delete;
  YoloSegmenter& operator=(const YoloSegmenter&) = delete;

  using Segmenter::segment;
  Segmentation segment(const cv::Mat& bgr, TimeNs t_ns) override;
  std::string name() const override { return "yolo"; }

  /// The network input size (from the model).
  cv::Size inputSize() const;
  /// The output layout found at load.
  const YoloSegLayout& layout() const;
  const ClassList& classes() const;
  const YoloSegOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plslam
