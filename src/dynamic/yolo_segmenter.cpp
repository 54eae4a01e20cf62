#include "dynamic/yolo_segmenter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam {
namespace {

const Logger kLog("dynamic");

std::vector<int64_t> matShape(const cv::Mat& m) {
  std::vector<int64_t> dims;
  for (int i = 0; i < m.dims; ++i) dims.push_back(m.size[i]);
  return dims;
}

void validate(const YoloSegOptions& o) {
  auto bad = [](const std::string& what) { throw ConfigError("yolo segmenter: " + what); };
  if (o.model_path.empty()) bad("model_path is empty");
  if (!(o.confidence > 0 && o.confidence < 1)) bad(str("confidence ", o.confidence, " outside (0, 1)"));
  if (!(o.nms_iou > 0 && o.nms_iou <= 1)) bad(str("nms_iou ", o.nms_iou, " outside (0, 1]"));
  if (!(o.mask_threshold > 0 && o.mask_threshold < 1)) bad(str("mask_threshold ", o.mask_threshold, " outside (0, 1)"));
  if (o.max_instances < 1 || o.max_instances > 65535) bad(str("max_instances ", o.max_instances, " outside 1..65535"));
  if (o.input_size < 0 || o.input_size > 4096) bad(str("input_size ", o.input_size, " outside 0..4096"));
  if (o.threads != 0)
    bad(str("threads ", o.threads,
            ": OpenCV 4.6's DNN cannot limit the threads of one network; only 0 (OpenCV's process-wide "
            "pool, set by the application with cv::setNumThreads or OPENCV_FOR_THREADS_NUM) is accepted"));
}

}  // namespace

// ---------------------------------------------------------------- letterbox geometry

Letterbox makeLetterbox(cv::Size image, cv::Size input) {
  if (image.empty() || input.empty())
    throw DataError(str("letterbox: empty size (image ", image.width, "x", image.height, ", input ", input.width, "x",
                        input.height, ")"));
  Letterbox lb;
  lb.image = image;
  lb.input = input;
  const double s = std::min(static_cast<double>(input.width) / image.width,
                            static_cast<double>(input.height) / image.height);
  lb.resized.width = std::clamp(static_cast<int>(std::lround(image.width * s)), 1, input.width);
  lb.resized.height = std::clamp(static_cast<int>(std::lround(image.height * s)), 1, input.height);
  // The exact per-axis factors of the resize (they differ from s by the rounding only).
  lb.scale_x = static_cast<double>(lb.resized.width) / image.width;
  lb.scale_y = static_cast<double>(lb.resized.height) / image.height;
  lb.pad_x = (input.width - lb.resized.width) / 2;
  lb.pad_y = (input.height - lb.resized.height) / 2;
  return lb;
}

cv::Point2d Letterbox::imageToInput(const cv::Point2d& p) const {
  return {p.x * scale_x + pad_x, p.y * scale_y + pad_y};
}

cv::Point2d Letterbox::inputToImage(const cv::Point2d& p) const {
  return {(p.x - pad_x) / scale_x, (p.y - pad_y) / scale_y};
}

cv::Rect Letterbox::boxToImage(const cv::Rect2d& input_box) const {
  const cv::Point2d a = inputToImage(input_box.tl());
  const cv::Point2d b = inputToImage(input_box.br());
  constexpr double eps = 1e-6;  // a box edge on a pixel border (up to rounding) does not take the next pixel
  const int x0 = static_cast<int>(std::floor(a.x + eps)), y0 = static_cast<int>(std::floor(a.y + eps));
  const int x1 = static_cast<int>(std::ceil(b.x - eps)), y1 = static_cast<int>(std::ceil(b.y - eps));
  return cv::Rect(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)) & cv::Rect(cv::Point(0, 0), image);
}

cv::Mat applyLetterbox(const cv::Mat& image, const Letterbox& lb) {
  if (image.size() != lb.image)
    throw DataError(str("letterbox: image ", image.cols, "x", image.rows, " but the letterbox is for ",
                        lb.image.width, "x", lb.image.height));
  cv::Mat resized, out;
  if (lb.resized == image.size())
    resized = image;
  else
    cv::resize(image, resized, lb.resized, 0, 0, cv::INTER_LINEAR);
  cv::copyMakeBorder(resized, out, lb.pad_y, lb.input.height - lb.resized.height - lb.pad_y, lb.pad_x,
                     lb.input.width - lb.resized.width - lb.pad_x, cv::BORDER_CONSTANT, cv::Scalar::all(114));
  return out;
}

cv::Mat unletterboxMap(const cv::Mat& map, const Letterbox& lb, const cv::Rect& roi) {
  CV_Assert(map.type() == CV_32FC1 && !map.empty());
  if (roi.empty()) return cv::Mat(roi.size(), CV_32FC1);
  // Image pixel centre x + 0.5 -> input (x + 0.5) * scale + pad -> map units * g -> map index - 0.5.
  const double gx = static_cast<double>(map.cols) / lb.input.width;
  const double gy = static_cast<double>(map.rows) / lb.input.height;
  cv::Matx23d M(gx * lb.scale_x, 0, gx * ((roi.x + 0.5) * lb.scale_x + lb.pad_x) - 0.5,  //
                0, gy * lb.scale_y, gy * ((roi.y + 0.5) * lb.scale_y + lb.pad_y) - 0.5);
  cv::Mat out;
  cv::warpAffine(map, out, M, roi.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  return out;
}

// ---------------------------------------------------------------- the segmenter

struct YoloSegmenter::Impl {
  YoloSegOptions options;
  ClassList classes;
  cv::dnn::Net net;
  std::vector<std::string> output_names;
  cv::Size input;
  YoloSegLayout layout;
  int proto_output = 1;

  Impl(const YoloSegOptions& o, ClassList c) : options(o), classes(std::move(c)) {}
  void load();
};

void YoloSegmenter::Impl::load() {
  const std::string& path = options.model_path;
  const OnnxModelInfo info = inspectOnnxFile(path);  // IoError for a missing / non-ONNX file

  // The input: one image tensor [1, 3, H, W].
  if (info.inputs.size() != 1)
    throw DataError(str("model '", path, "': ", info.inputs.size(),
                        " graph inputs; a YOLOv8-seg model has one image input [1, 3, H, W]"));
  const auto& in = info.inputs[0].dims;
  if (in.size() != 4 || (in[1] >= 0 && in[1] != 3))
    throw DataError(str("model '", path, "': input '", info.inputs[0].name, "' is ", shapeToString(in),
                        "; a YOLOv8-seg model takes [1, 3, H, W]"));
  if (in[2] > 0 && in[3] > 0) {
    input = cv::Size(static_cast<int>(in[3]), static_cast<int>(in[2]));
    if (options.input_size > 0 && (input.width != options.input_size || input.height != options.input_size))
      throw ConfigError(str("yolo segmenter: input_size ", options.input_size, " but model '", path,
                            "' has a fixed input of ", input.width, "x", input.height));
  } else if (options.input_size > 0) {
    input = cv::Size(options.input_size, options.input_size);
  } else {
    throw DataError(str("model '", path, "': input '", info.inputs[0].name, "' ", shapeToString(in),
                        " does not fix the image size; set the input_size option"));
  }
  // The declared outputs, when the file gives all their shapes (unknown dimensions are
  // checked after the trial run).
  std::vector<std::vector<int64_t>> declared;
  bool all_shaped = true;
  for (const auto& o : info.outputs) {
    declared.push_back(o.dims);
    all_shaped = all_shaped && !o.dims.empty();
  }
  if (info.outputs.size() != 2 || all_shaped) checkYoloSegOutputs(declared, path);

  try {
    net = cv::dnn::readNetFromONNX(path);
  } catch (const cv::Exception& e) {
    throw IoError(str("model '", path, "': OpenCV cannot load it: ", e.what()));
  }
  if (net.empty()) throw IoError(str("model '", path, "': OpenCV loaded an empty network"));
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  output_names = net.getUnconnectedOutLayersNames();

  // One trial run on a grey input: the real output shapes.
  std::vector<cv::Mat> outs;
  try {
    cv::Mat blob(std::vector<int>{1, 3, input.height, input.width}, CV_32F, cv::Scalar(114.0 / 255.0));
    net.setInput(blob);
    net.forward(outs, output_names);
  } catch (const cv::Exception& e) {
    throw DataError(str("model '", path, "': OpenCV cannot run it on a ", input.width, "x", input.height,
                        " input: ", e.what()));
  }
  std::vector<std::vector<int64_t>> shapes;
  for (const auto& m : outs) shapes.push_back(matShape(m));
  layout = checkYoloSegOutputs(shapes, path);
  proto_output = 1 - layout.detections_output;
  if (static_cast<int>(classes.size()) != layout.num_classes)
    throw ConfigError(str("class list ", classes.source(), " has ", classes.size(), " names but model '", path,
                          "' scores ", layout.num_classes, " classes"));
  kLog.info(str("yolo segmenter: ", path, ", input ", input.width, "x", input.height, ", ", layout.num_classes,
                " classes, ", layout.num_anchors, " anchors, prototypes ", layout.num_masks, "x",
                layout.proto_height, "x", layout.proto_width));
}

YoloSegmenter::YoloSegmenter(const YoloSegOptions& options, ClassList classes)
    : impl_(std::make_unique<Impl>(options, std::move(classes))) {
  validate(options);
  impl_->load();
}

YoloSegmenter::~YoloSegmenter() = default;

cv::Size YoloSegmenter::inputSize() const { return impl_->input; }
const YoloSegLayout& YoloSegmenter::layout() const { return impl_->layout; }
const ClassList& YoloSegmenter::classes() const { return impl_->classes; }
const YoloSegOptions& YoloSegmenter::options() const { return impl_->options; }

namespace {

struct Candidate {
  int anchor, class_id;
  float score;
  cv::Rect2d box;
};

/// Per anchor its best class over the confidence; class-aware NMS; best scores first, at
/// most max_instances. `anchors` holds one row per anchor: cx cy w h, class scores, mask coefficients.
std::vector<Candidate> selectDetections(const cv::Mat& anchors, const YoloSegLayout& L, const YoloSegOptions& o) {
  std::map<int, std::vector<Candidate>> by_class;
  for (int a = 0; a < L.num_anchors; ++a) {
    const float* r = anchors.ptr<float>(a);
    const float* scores = r + 4;
    const int best = static_cast<int>(std::max_element(scores, scores + L.num_classes) - scores);
    if (scores[best] < o.confidence) continue;
    by_class[best].push_back({a, best, scores[best], cv::Rect2d(r[0] - 0.5 * r[2], r[1] - 0.5 * r[3], r[2], r[3])});
  }
  std::vector<Candidate> kept;
  for (auto& [cls, cands] : by_class) {
    std::vector<cv::Rect2d> boxes;
    std::vector<float> scores;
    for (const auto& c : cands) {
      boxes.push_back(c.box);
      scores.push_back(c.score);
    }
    std::vector<int> keep;
    cv::dnn::NMSBoxes(boxes, scores, o.confidence, o.nms_iou, keep);
    for (int i : keep) kept.push_back(cands[i]);
  }
  std::sort(kept.begin(), kept.end(), [](const Candidate& a, const Candidate& b) {
    return a.score != b.score ? a.score > b.score : a.anchor < b.anchor;  // deterministic ties
  });
  if (static_cast<int>(kept.size()) > o.max_instances) kept.resize(o.max_instances);
  return kept;
}

/// Mask probabilities of the kept detections on the prototype grid: sigmoid(coeffs x protos),
/// one row per detection.
cv::Mat maskProbabilities(const cv::Mat& anchors, const cv::Mat& protos, const std::vector<Candidate>& kept,
                          const YoloSegLayout& L) {
  const int rows = 4 + L.num_classes + L.num_masks;
  cv::Mat coeffs(static_cast<int>(kept.size()), L.num_masks, CV_32F);
  for (size_t k = 0; k < kept.size(); ++k)
    anchors.row(kept[k].anchor).colRange(4 + L.num_classes, rows).copyTo(coeffs.row(static_cast<int>(k)));
  const cv::Mat proto2d(L.num_masks, L.proto_height * L.proto_width, CV_32F, const_cast<float*>(protos.ptr<float>()));
  cv::Mat logits = coeffs * proto2d, prob;
  cv::exp(-logits, prob);
  prob = 1.0 / (1.0 + prob);
  return prob;
}

}  // namespace

Segmentation YoloSegmenter::segment(const cv::Mat& bgr, TimeNs t_ns) {
  const auto t0 = std::chrono::steady_clock::now();
  if (bgr.empty()) throw DataError(str("yolo segmenter: empty image at t_ns ", t_ns));
  if (bgr.type() != CV_8UC3)
    throw DataError(str("yolo segmenter: image at t_ns ", t_ns, " is not CV_8UC3 (type ", bgr.type(), ")"));
  Impl& m = *impl_;
  const YoloSegLayout& L = m.layout;
  const YoloSegOptions& o = m.options;

  const Letterbox lb = makeLetterbox(bgr.size(), m.input);
  const cv::Mat blob = cv::dnn::blobFromImage(applyLetterbox(bgr, lb), 1.0 / 255.0, cv::Size(), cv::Scalar(),
                                              /*swapRB=*/true, /*crop=*/false, CV_32F);
  std::vector<cv::Mat> outs;
  try {
    m.net.setInput(blob);
    m.net.forward(outs, m.output_names);
  } catch (const cv::Exception& e) {
    throw DataError(str("yolo segmenter: forward pass failed at t_ns ", t_ns, ": ", e.what()));
  }
  const cv::Mat& det = outs[L.detections_output];
  const cv::Mat& protos = outs[m.proto_output];
  const int rows = 4 + L.num_classes + L.num_masks;
  if (det.total() != static_cast<size_t>(rows) * L.num_anchors ||
      protos.total() != static_cast<size_t>(L.num_masks) * L.proto_height * L.proto_width)
    throw DataError("yolo segmenter: output sizes changed since the model was loaded");

  // One row per anchor: cx cy w h, class scores, mask coefficients (input pixels).
  cv::Mat anchors;
  cv::transpose(cv::Mat(rows, L.num_anchors, CV_32F, const_cast<float*>(det.ptr<float>())), anchors);
  const std::vector<Candidate> kept = selectDetections(anchors, L, o);

  Segmentation s;
  s.t_ns = t_ns;
  s.instance_ids = cv::Mat::zeros(bgr.size(), CV_16UC1);
  if (!kept.empty()) {
    const cv::Mat prob = maskProbabilities(anchors, protos, kept, L);
    for (size_t k = 0; k < kept.size(); ++k) {
      const Candidate& c = kept[k];
      const cv::Rect box = lb.boxToImage(c.box);
      if (box.empty()) continue;
      const cv::Mat map = prob.row(static_cast<int>(k)).reshape(1, L.proto_height);
      const cv::Mat inside = unletterboxMap(map, lb, box) > o.mask_threshold;  // cut to the box by construction
      if (cv::countNonZero(inside) == 0) continue;
      Instance inst;
      inst.id = static_cast<int>(s.instances.size()) + 1;
      inst.class_id = c.class_id;
      inst.class_name = m.classes.name(c.class_id);
      inst.score = c.score;
      inst.box = box;
      inst.potentially_dynamic = m.classes.isDynamic(c.class_id);
      // Higher scores come first: an instance only takes pixels no better one has.
      cv::Mat labels = s.instance_ids(box);
      labels.setTo(cv::Scalar(inst.id), inside & (labels == 0));
      s.instances.push_back(std::move(inst));
    }
  }
  s.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace plslam
