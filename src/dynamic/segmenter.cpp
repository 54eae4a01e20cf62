#include "dynamic/segmenter.h"

#include <chrono>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/profile.h"
#include "core/error.h"
#include "core/log.h"
#include "core/option_table.h"
#include "dynamic/yolo_segmenter.h"

namespace plslam {
namespace {

const Logger kLog("dynamic");


void checkImage(const cv::Mat& bgr, TimeNs t_ns, const char* who) {
  if (bgr.empty()) throw DataError(str(who, " segmenter: empty image at t_ns ", t_ns));
  if (bgr.type() != CV_8UC3)
    throw DataError(str(who, " segmenter: image at t_ns ", t_ns, " is not CV_8UC3 (type ", bgr.type(), ")"));
}

}  // namespace

const char* segmenterKindName(SegmenterKind kind) {
  switch (kind) {
    case SegmenterKind::kNone: return "none";
    case SegmenterKind::kReplay: return "replay";
    case SegmenterKind::kYolo: return "yolo";
  }
  return "?";
}

SegmenterKind parseSegmenterKind(const std::string& name) {
  for (SegmenterKind k : {SegmenterKind::kNone, SegmenterKind::kReplay, SegmenterKind::kYolo})
    if (name == segmenterKindName(k)) return k;
  throw ConfigError(str("unknown segmenter '", name, "' (accepted: none, replay, yolo)"));
}

void bindSegmenterOptions(OptionTable* t, SegmenterOptions* o) {
  t->bindCustom(
      "segmenter.backend", fieldSpan(&o->kind),
      [o](const std::string& v) {
        try {
          o->kind = parseSegmenterKind(v);
        } catch (const ConfigError&) {
          throw std::invalid_argument("expected none, replay or yolo");
        }
      },
      [o] { return std::string(segmenterKindName(o->kind)); }, "none, replay or yolo",
      "instance masks: none (geometric checks only), replay (the folder's masks/, as plslam synth writes them) or "
      "yolo (the model of segmenter.model); --segmenter overrides it");
  t->bind("segmenter.model", &o->yolo.model_path, "YOLOv8-seg .onnx model of the yolo backend (--segmenter FILE.onnx overrides it)");
  t->bind("segmenter.classes", &o->classes_file,
          "class names file, one a line, in the model's order (empty: the COCO names; --classes overrides it)");
  t->bindCustom(
      "segmenter.dynamic_classes", fieldSpan(&o->dynamic_classes),
      [o](const std::string& v) {
        if (splitCommaList(v).empty()) o->dynamic_classes.reset();
        else o->dynamic_classes = splitCommaList(v);
      },
      [o] {
        std::string joined;
        for (const std::string& n : o->dynamic_classes.value_or(std::vector<std::string>{}))
          joined += (joined.empty() ? "" : ",") + n;
        return joined;
      },
      "text",
      "comma-separated class names that may move (empty: person, vehicles, animals; --dynamic-classes overrides it)");
  t->bind("segmenter.allow_missing_model", &o->allow_missing_model,
          "if the model cannot be used, warn and go on with the geometric checks only (--allow-missing-model sets it)");
}

ClassList makeClassList(const SegmenterOptions& options) {
  ClassList classes = options.classes_file.empty() ? ClassList::coco() : ClassList::load(options.classes_file);
  if (options.dynamic_classes) classes.setDynamic(*options.dynamic_classes);
  return classes;
}

std::unique_ptr<Segmenter> makeSegmenter(const SegmenterOptions& options, std::string* fallback_reason) {
  if (fallback_reason) fallback_reason->clear();
  switch (options.kind) {
    case SegmenterKind::kNone:
      return std::make_unique<NoneSegmenter>();
    case SegmenterKind::kReplay:
      return std::make_unique<ReplaySegmenter>(options.replay_labels, makeClassList(options));
    case SegmenterKind::kYolo: {
      ClassList classes = makeClassList(options);  // a bad class file is a configuration problem: thrown
      try {
        return std::make_unique<YoloSegmenter>(options.yolo, std::move(classes));
      } catch (const ConfigError&) {
        throw;
      } catch (const Error& e) {  // IoError / DataError: the model itself
        if (!options.allow_missing_model) throw;
        kLog.warn(str("segmenter: ", e.what(), "; going on without segmentation (geometry only)"));
        if (fallback_reason) *fallback_reason = e.what();
        return std::make_unique<NoneSegmenter>();
      }
    }
  }
  throw ConfigError("makeSegmenter: invalid segmenter kind");
}

Segmentation NoneSegmenter::segment(const cv::Mat& bgr, TimeNs t_ns) {
  const auto t0 = std::chrono::steady_clock::now();
  checkImage(bgr, t_ns, "none");
  Segmentation s;
  s.t_ns = t_ns;
  s.instance_ids = cv::Mat::zeros(bgr.size(), CV_16UC1);
  s.ms = msSince(t0);
  return s;
}

ReplaySegmenter::ReplaySegmenter(std::vector<InstanceClass> labels, ClassList classes, MaskSource source)
    : labels_(std::move(labels)), classes_(std::move(classes)), source_(std::move(source)) {
  for (size_t i = 0; i < labels_.size(); ++i) {
    if (labels_[i].instance_id < 1 || labels_[i].instance_id > 65535)
      throw ConfigError(str("replay segmenter: instance id ", labels_[i].instance_id,
                            " out of the 16-bit mask range 1..65535"));
    for (size_t j = 0; j < i; ++j)
      if (labels_[j].instance_id == labels_[i].instance_id)
        throw ConfigError(str("replay segmenter: instance id ", labels_[i].instance_id, " labelled twice"));
  }
}

Segmentation ReplaySegmenter::segment(const cv::Mat& bgr, TimeNs t_ns) {
  return replay(bgr, source_ ? source_(t_ns) : cv::Mat(), t_ns);
}

Segmentation ReplaySegmenter::segment(const RgbdFrame& frame) {
  return replay(frame.bgr, frame.instance_ids, frame.t_ns);
}

Segmentation ReplaySegmenter::replay(const cv::Mat& bgr, const cv::Mat& mask, TimeNs t_ns) {
  const auto t0 = std::chrono::steady_clock::now();
  checkImage(bgr, t_ns, "replay");
  Segmentation s;
  if (mask.empty()) {
    ++frames_without_mask_;
    s.t_ns = t_ns;
    s.instance_ids = cv::Mat::zeros(bgr.size(), CV_16UC1);
  } else {
    s = fromMask(mask, t_ns, bgr.size());
  }
  s.ms = msSince(t0);
  return s;
}

Segmentation ReplaySegmenter::fromMask(const cv::Mat& ids, TimeNs t_ns, cv::Size image_size) const {
  const auto t0 = std::chrono::steady_clock::now();
  if (ids.empty() || ids.type() != CV_16UC1)
    throw DataError(str("replay segmenter: mask at t_ns ", t_ns, " is ", ids.empty() ? "empty" : "not CV_16UC1"));
  if (!image_size.empty() && ids.size() != image_size)
    throw DataError(str("replay segmenter: mask at t_ns ", t_ns, " is ", ids.cols, "x", ids.rows, ", the image ",
                        image_size.width, "x", image_size.height));
  // Bounding box of every id present.
  struct Extent {
    int x0, y0, x1, y1;
  };
  std::map<int, Extent> extents;
  for (int y = 0; y < ids.rows; ++y) {
    const uint16_t* row = ids.ptr<uint16_t>(y);
    for (int x = 0; x < ids.cols; ++x) {
      if (!row[x]) continue;
      auto [it, fresh] = extents.try_emplace(row[x], Extent{x, y, x, y});
      if (!fresh) {
        Extent& e = it->second;
        e.x0 = std::min(e.x0, x);
        e.x1 = std::max(e.x1, x);
        e.y1 = y;  // rows are scanned in order
      }
    }
  }
  Segmentation s;
  s.t_ns = t_ns;
  std::vector<uint16_t> lut(65536, 0);
  for (const auto& [source_id, e] : extents) {
    Instance inst;
    inst.id = static_cast<int>(s.instances.size()) + 1;
    inst.source_id = source_id;
    inst.score = 1.0f;
    inst.box = cv::Rect(e.x0, e.y0, e.x1 - e.x0 + 1, e.y1 - e.y0 + 1);
    const InstanceClass* label = nullptr;
    for (const auto& l : labels_)
      if (l.instance_id == source_id) label = &l;
    if (!label) {
      inst.class_id = -1;
      inst.class_name = "unknown";
      inst.potentially_dynamic = true;
    } else {
      inst.class_id = label->class_id;
      inst.class_name = label->class_name.empty() ? classes_.name(label->class_id) : label->class_name;
      const int known = label->class_name.empty() ? label->class_id : classes_.find(label->class_name);
      inst.potentially_dynamic = known < 0 || known >= static_cast<int>(classes_.size()) || classes_.isDynamic(known);
    }
    lut[source_id] = static_cast<uint16_t>(inst.id);
    s.instances.push_back(std::move(inst));
  }
  s.instance_ids.create(ids.size(), CV_16UC1);
  for (int y = 0; y < ids.rows; ++y) {
    const uint16_t* in = ids.ptr<uint16_t>(y);
    uint16_t* out = s.instance_ids.ptr<uint16_t>(y);
    for (int x = 0; x < ids.cols; ++x) out[x] = lut[in[x]];
  }
  s.ms = msSince(t0);
  return s;
}

}  // namespace plslam
