// The configuration keys of a run: every option a YAML configuration file may set, bound
// to its field (its default is the field's initial value). Keep one line per field.
#include "dense/dense_options.h"
#include "dynamic/segmenter.h"
#include "frontend/dynamic_filter.h"
#include "frontend/feature_extraction.h"
#include "frontend/tracker.h"
#include "loop/loop_closer.h"
#include "mapping/local_mapper.h"
#include "system/system.h"

namespace plslam {

namespace {

// The dynamic filter, and the segmenter it drives.
void bindDynamicOptions(OptionTable* t, SystemOptions* o) {
  bindDynamicFilterOptions(t, &o->dynamic);
  t->bind("dynamic.yolo_confidence", &o->segmenter.yolo.confidence, "YOLOv8-seg minimum class score");
  t->bind("dynamic.yolo_nms_iou", &o->segmenter.yolo.nms_iou, "YOLOv8-seg class-aware NMS overlap");
  t->bind("dynamic.yolo_mask_threshold", &o->segmenter.yolo.mask_threshold,
          "YOLOv8-seg mask probability above which a pixel is the instance's");
  t->bind("dynamic.yolo_max_instances", &o->segmenter.yolo.max_instances, "YOLOv8-seg instances kept per image (the best scores)");
  t->bind("dynamic.yolo_input_size", &o->segmenter.yolo.input_size,
          "YOLOv8-seg square input side for a model whose input size is symbolic (0: read it from the model)");
  bindSegmenterOptions(t, &o->segmenter);
}

// Loop closure, with the system switches of the threads that run behind tracking.
void bindLoopAndBackgroundOptions(OptionTable* t, SystemOptions* o) {
  t->bind("system.use_loop", &o->use_loop, "loop closure (place recognition, verification, pose graph)");
  t->bind("system.refine_frames", &o->refine_frames, "re-estimate each frame's pose once local BA has refined its landmarks");
  t->bind("system.refine_after_keyframes", &o->refine_after_keyframes, "refine a frame when this many keyframes have been made since it");
  t->bind("system.refine_after_frames", &o->refine_after_frames, "... or this many frames");
  t->bind("system.background_nice", &o->background_nice,
          "nice value (0-19) of the mapping and loop threads, so that tracking wins the cores when both want them");
  bindLoopOptions(t, &o->loop);
}

void bindCalibrationOptions(OptionTable* t, SystemOptions* o) {
  t->bind("calibration.camera_to_base", &o->camera_to_base,
          "camera-to-base file of plslam calib base: the map frame's origin is then on the floor below the base, x its "
          "forward, and trajectory_base.txt is written (empty: none)");
  t->bind("calibration.depth_scale", &o->depth_correction.scale,
          "depth correction of plslam calib depth: measured = scale * true + offset (1: none)");
  t->bind("calibration.depth_offset_m", &o->depth_correction.offset_m, "... and its offset (m, 0: none)");
}

}  // namespace

// In this order: the table lists keys in binding order, and writes them grouped by section.
void bindOptions(OptionTable* t, SystemOptions* o) {
  t->bind("system.sequential", &o->sequential, "run all stages on one thread in a fixed order (deterministic)");
  t->bind("system.use_lines", &o->use_lines, "use line features in tracking and mapping");
  t->bind("system.mapping_queue", &o->mapping_queue, "keyframes waiting for local mapping before tracking waits");

  bindFeatureOptions(t, &o->features);
  bindTrackerOptions(t, &o->tracker);
  bindDynamicOptions(t, o);
  bindLoopAndBackgroundOptions(t, o);
  bindDenseOptions(t, &o->dense);
  bindCalibrationOptions(t, o);
  bindLocalMapperOptions(t, &o->mapper);
}

}  // namespace plslam
