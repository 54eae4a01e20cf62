// The segmenter interface, its options and factory, and the two simple backends:
//   none    no instances (instance_ids is still a zero image of the frame size)
//   replay  instances from given instance-id masks (the synthetic datasets' masks/, or any
//           CV_16U label image with a table of the ids' classes)
//   yolo    YOLOv8-seg through OpenCV DNN (dynamic/yolo_segmenter.h)
//
// Every backend returns a Segmentation whose instance_ids has the image size, 0 where no
// instance is and k where instances[k-1] is (ids 1..K, compact, in the backend's order:
// decreasing score for yolo, increasing source id for replay), and whose ms is the time
// the call took.
//
// Thread safety: a Segmenter is used from one thread at a time (the yolo backend runs one
// network); different instances are independent.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.h"
#include "core/time.h"
#include "dynamic/class_list.h"
#include "dynamic/instance.h"

namespace plslam {

class OptionTable;

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  /// Segments a CV_8UC3 BGR image taken at t_ns. Throws DataError for an empty image or
  /// one of another type.
  virtual Segmentation segment(const cv::Mat& bgr, TimeNs t_ns) = 0;
  /// Segments a frame; the default uses frame.bgr and frame.t_ns (replay reads frame.instance_ids).
  virtual Segmentation segment(const RgbdFrame& frame) { return segment(frame.bgr, frame.t_ns); }
  /// "none", "replay", "yolo".
  virtual std::string name() const = 0;
};

enum class SegmenterKind { kNone, kReplay, kYolo };
/// "none", "replay", "yolo".
const char* segmenterKindName(SegmenterKind kind);
/// The inverse of segmenterKindName; throws ConfigError listing the accepted names.
SegmenterKind parseSegmenterKind(const std::string& name);

/// The class of one id of a replayed mask (as masks/instances.txt lists it).
struct InstanceClass {
  int instance_id = 0;     ///< the value of the object's pixels in the masks
  int class_id = -1;       ///< class id (COCO: 0 person)
  std::string class_name;  ///< class name (decides potentially_dynamic through the class list)
};

/// Options of the YOLOv8-seg backend.
/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindDynamicOptions (system/system_options.cpp), bindSegmenterOptions (dynamic/segmenter.cpp).
/// `plslam run --print-config` lists them.
struct YoloSegOptions {
  std::string model_path;
  float confidence = 0.35f;
  float nms_iou = 0.5f;
  float mask_threshold = 0.5f;
  int max_instances = 100;
  int input_size = 0;
  /// Threads of the forward pass. Only 0 (OpenCV's process-wide pool, cv::setNumThreads) is
  /// accepted: OpenCV 4.6's DNN has no per-network thread limit and this library does not
  /// change the process-wide setting. Other values are refused with ConfigError.
  int threads = 0;
};

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindSegmenterOptions (dynamic/segmenter.cpp). `plslam run --print-config` lists them.
struct SegmenterOptions {
  SegmenterKind kind = SegmenterKind::kNone;
  std::string classes_file;
  // An unknown name is a ConfigError (unset: ClassList::defaultDynamicNames()).
  std::optional<std::vector<std::string>> dynamic_classes;
  YoloSegOptions yolo;                        ///< kYolo
  std::vector<InstanceClass> replay_labels;   ///< kReplay: the classes of the mask ids
  // The backend falls back to none on IoError/DataError from the model.
  bool allow_missing_model = false;
};

/// Binds the segmenter's configuration keys to `options` (their doc strings are the
/// reference): segmenter.backend, segmenter.model, segmenter.classes,
/// segmenter.dynamic_classes, segmenter.allow_missing_model. A bad backend is a ConfigError
/// naming the key. Each switch of `plslam run` (--segmenter, --classes, ...) overrides its key.
void bindSegmenterOptions(OptionTable* table, SegmenterOptions* options);

/// The class list the options describe (classes_file or the built-in COCO list, with
/// the dynamic set applied). Throws IoError / ConfigError.
ClassList makeClassList(const SegmenterOptions& options);

/// Builds the backend. Throws ConfigError for bad options, IoError / DataError for an
/// unusable model or class file (naming the file), unless allow_missing_model turns a
/// model problem into the none backend; then `fallback_reason` (when given) receives the
/// message, and stays empty otherwise.
std::unique_ptr<Segmenter> makeSegmenter(const SegmenterOptions& options, std::string* fallback_reason = nullptr);

/// No instances.
class NoneSegmenter : public Segmenter {
 public:
  using Segmenter::segment;
  Segmentation segment(const cv::Mat& bgr, TimeNs t_ns) override;
  std::string name() const override { return "none"; }
};

/// Instances from given CV_16U instance-id masks. Ids of the mask become instances 1..K in
/// increasing order of the mask id (kept in Instance::source_id), boxes are the bounding
/// boxes of their pixels, score 1, class from the labels. An id without a label is class
/// -1 "unknown"; a class the class list does not know is potentially dynamic (the masks
/// were given because the objects may move); otherwise the list's dynamic set decides.
class ReplaySegmenter : public Segmenter {
 public:
  /// Gives the mask of time t (an empty Mat when there is none).
  using MaskSource = std::function<cv::Mat(TimeNs t_ns)>;

  explicit ReplaySegmenter(std::vector<InstanceClass> labels, ClassList classes = ClassList::coco(),
                           MaskSource source = {});
  using Segmenter::segment;
  /// The mask from the MaskSource (no source, or no mask at t: no instances, counted).
  Segmentation segment(const cv::Mat& bgr, TimeNs t_ns) override;
  /// The mask of the frame (frame.instance_ids; none: no instances, counted).
  Segmentation segment(const RgbdFrame& frame) override;
  std::string name() const override { return "replay"; }

  /// The segmentation of one mask. Throws DataError when the mask is not CV_16UC1 or its
  /// size differs from `image_size` (when image_size is not empty).
  Segmentation fromMask(const cv::Mat& instance_ids, TimeNs t_ns, cv::Size image_size = {}) const;
  /// Calls that had no mask to replay.
  int framesWithoutMask() const { return frames_without_mask_; }

 private:
  Segmentation replay(const cv::Mat& bgr, const cv::Mat& mask, TimeNs t_ns);
  std::vector<InstanceClass> labels_;
  ClassList classes_;
  MaskSource source_;
  int frames_without_mask_ = 0;
};

}  // namespace plslam
