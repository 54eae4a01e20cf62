// plslam eval masks: how well the instance masks used per frame cover the moving objects
// when the masks come late, with and without carrying them to the frame (propagation).
//
// The folder's masks/ are both the segmenter (replayed, delivered dynamic.replay_latency_frames
// late) and the truth (the masks of the frame itself). The dynamic filter runs sequentially on
// every frame, as in a run (the threaded mode with a latency uses the very same masks); the
// pixels of its instances are compared with the true instances' pixels, summed over all
// frames, and so are the pixels its fused dynamic mask removes.
#include <cstdio>
#include <iostream>
#include <sstream>

#include "camera/camera_file.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/mask_overlap.h"
#include "frontend/dynamic_filter.h"
#include "frontend/feature_extraction.h"
#include "run_session.h"

namespace plslam::cli {

namespace {

struct Variant {
  int latency = 0;
  bool propagate = false;
  std::unique_ptr<DynamicFilter> filter;
  MaskOverlap instances;  ///< the instance masks used
  MaskOverlap removed;    ///< the fused dynamic mask
};

std::vector<int> parseLatencies(const std::string& text) {
  std::vector<int> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      size_t used = 0;
      const int k = std::stoi(item, &used);
      if (used != item.size() || k < 0) throw std::invalid_argument(item);
      out.push_back(k);
    } catch (const std::exception&) {
      throw ConfigError("plslam eval masks: --latencies expects whole numbers >= 0 separated by commas, got '" + text + "'");
    }
  }
  if (out.empty()) throw ConfigError("plslam eval masks: --latencies is empty");
  return out;
}

std::vector<Variant> makeVariants(const std::vector<int>& latencies, const SystemOptions& options,
                                  const SegmenterOptions& so, const PinholeCamera& camera) {
  std::vector<Variant> out;
  for (const int k : latencies)
    for (const bool propagate : {false, true}) {
      DynamicFilterOptions o = options.dynamic;
      o.latency_frames = k;
      o.propagate_masks = propagate;
      Variant v;
      v.latency = k;
      v.propagate = propagate;
      v.filter = std::make_unique<DynamicFilter>(camera, o, makeSegmenter(so), false);
      out.push_back(std::move(v));
    }
  return out;
}

// Scores one frame into the variant's sums; one CSV line for it when `csv` is given.
void scoreFrame(const RgbdFrame& frame, const FrameFeatures& features, Variant* v, std::ostream* csv) {
  FrameFeatures f = features;
  const DynamicFrameResult r = v->filter->process(frame, &f, std::nullopt);
  MaskOverlap instances, removed;
  instances.add(r.segmentation.instance_ids, frame.instance_ids);
  removed.add(r.mask.empty() ? cv::Mat() : cv::Mat(r.mask == 0), frame.instance_ids);
  for (auto [sum, one] : {std::pair{&v->instances, &instances}, {&v->removed, &removed}}) {
    sum->true_positive += one->true_positive;
    sum->false_positive += one->false_positive;
    sum->false_negative += one->false_negative;
  }
  if (csv)
    *csv << frame.index << ',' << formatSecondsStamp(frame.t_ns) << ',' << v->latency << ',' << v->propagate << ','
         << r.mask_age_frames << ',' << instances.true_positive << ',' << instances.false_positive << ','
         << instances.false_negative << ',' << removed.true_positive << ',' << removed.false_positive << ','
         << removed.false_negative << '\n';
}

void printTable(const std::vector<Variant>& variants, int frames) {
  std::printf("%d frames; pixels summed over them (precision, recall, IoU against the true instance masks)\n", frames);
  std::printf("%-8s %-11s | %-27s | %-19s\n", "latency", "masks", "instance masks P / R / IoU", "removed P / R");
  for (const Variant& v : variants)
    std::printf("%-8d %-11s | %.3f / %.3f / %.3f       | %.3f / %.3f\n", v.latency,
                v.propagate ? "carried" : "stale", v.instances.precision(), v.instances.recall(), v.instances.iou(),
                v.removed.precision(), v.removed.recall());
}

}  // namespace

int runEvalMasks(int argc, char** argv) {
  Args args("eval masks", "Precision and recall of late instance masks, stale and propagated, against the true masks.");
  args.option("dataset", "folder with masks.txt and masks/ (plslam synth writes them)", "", true)
      .option("calib", "camera file (ViSP XML); default: <dataset>/camera.xml")
      .option("config", "YAML run options (the dynamic.* keys apply; replay_latency_frames and propagate_masks are set per row)")
      .option("latencies", "mask latencies to compare, frames, comma-separated", "0,2,4,8")
      .option("max-frames", "only the first N frames (0 = all)", "0")
      .option("csv", "also write the pixel counts per frame and row to this CSV file")
      .epilog("example: plslam eval masks --dataset /tmp/crowded --latencies 0,2,4,8");
  if (!args.parse(argc, argv)) return 0;
  const std::vector<int> latencies = parseLatencies(args.str("latencies"));
  const int max_frames = args.integer("max-frames", 0, 1000000);
  SystemOptions options;
  OptionTable table;
  loadRunConfig(args.has("config") ? args.str("config") : std::string(), &options, &table);
  const std::string dir = args.str("dataset");
  const PinholeCamera camera = loadCameraFile(args.has("calib") ? args.str("calib") : dir + "/camera.xml");
  TumDataset dataset = TumDataset::open(dir, camera);
  SegmenterOptions so = options.segmenter;
  so.kind = SegmenterKind::kReplay;
  so.replay_labels = replayLabels(dataset);
  std::vector<Variant> variants = makeVariants(latencies, options, so, camera);

  FeatureOptions fo = options.features;
  fo.use_lines = false;  // the filter judges keypoints; lines do not change the masks
  std::ostringstream csv;
  csv << "frame,t_s,latency,propagated,mask_age,instances_tp,instances_fp,instances_fn,removed_tp,removed_fp,removed_fn\n";
  int frames = 0;
  RgbdFrame frame;
  while ((max_frames == 0 || frames < max_frames) && dataset.next(&frame)) {
    if (frame.instance_ids.empty()) throw IoError(dir + ": frame " + frame.name + " has no mask (masks.txt)");
    const FrameFeatures f = extractFeatures(frame, cv::Mat(), camera, fo);
    for (Variant& v : variants) scoreFrame(frame, f, &v, args.has("csv") ? &csv : nullptr);
    ++frames;
  }
  printTable(variants, frames);
  if (args.has("csv")) writeFileAtomically(args.str("csv"), csv.str());
  return 0;
}

}  // namespace plslam::cli
