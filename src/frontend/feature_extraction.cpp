#include "frontend/feature_extraction.h"

#include <cmath>
#include <future>
#include <opencv2/imgproc.hpp>

namespace plslam {

void bindFeatureOptions(OptionTable* t, FeatureOptions* o) {
  t->bind("features.orb_features", &o->orb.num_features, "ORB keypoints per image, over all pyramid levels");
  t->bind("features.orb_scale_factor", &o->orb.scale_factor, "ORB pyramid scale between levels");
  t->bind("features.orb_levels", &o->orb.num_levels, "ORB pyramid levels");
  t->bind("features.orb_fast_threshold", &o->orb.fast_threshold, "FAST threshold");
  t->bind("features.orb_min_fast_threshold", &o->orb.min_fast_threshold, "FAST threshold retried in the grid cells where orb_fast_threshold finds nothing");
  t->bind("features.line_detector", &o->lines.detector, "segment detector: lsd or fld (FastLineDetector)");
  t->bind("features.line_detect_scale", &o->lines.detect_scale, "the segment detector runs on the image resized by this (0.5: about 3 x faster, coarser endpoints)");
  t->bind("features.line_lsd_quant", &o->lines.lsd_quant, "LSD: gradient quantisation bound; larger ignores weaker edges and runs faster");
  t->bind("features.line_lbd_scale", &o->lines.lbd_scale, "LBD runs on the image resized by this (0.5: half the time, bands 14 px wide)");
  t->bind("features.line_fld_min_length_px", &o->lines.fld_min_length_px, "FLD: shortest segment, pixels of the resized image");
  t->bind("features.line_fld_canny_low", &o->lines.fld_canny_low, "FLD: Canny's low hysteresis threshold");
  t->bind("features.line_fld_canny_high", &o->lines.fld_canny_high, "FLD: Canny's high hysteresis threshold");
  t->bind("features.line_min_length_ratio", &o->lines.min_length_ratio, "shortest segment, fraction of the image diagonal");
  t->bind("features.line_max", &o->lines.max_lines, "segments kept per image (the longest)");
  t->bind("features.line_merge_angle_deg", &o->lines.merge_angle_deg, "merge fragments closer than this in direction (deg)");
  t->bind("features.line_merge_distance_px", &o->lines.merge_distance_px, "merge fragments this close to each other's line (px)");
  t->bind("features.line_merge_gap_px", &o->lines.merge_gap_px, "merge fragments at most this far apart along the line (px)");
  t->bind("features.orb_cell_size", &o->orb.cell_size,
          "side of the grid cells (level pixels) where FAST is retried at the low threshold");
  t->bind("features.line_lsd_refine", &o->lines.lsd_refine,
          "LSD: OpenCV's implementation with its refinement (about 4 x slower; the merge does most of its job)");
  t->bind("features.min_depth_m", &o->min_depth_m, "depth readings below this count as none (m)");
  t->bind("features.parallel", &o->parallel, "extract points and lines on two threads (the result does not depend on it)");
}

FeatureExtraction::FeatureExtraction(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera,
                                     const FeatureOptions& options, WorkerThread* line_worker)
    : frame_(frame), mask_(mask), camera_(camera), options_(options) {
  if (frame.bgr.empty()) return;
  if (frame.bgr.channels() == 3) cv::cvtColor(frame.bgr, grey_, cv::COLOR_BGR2GRAY);
  else grey_ = frame.bgr;
  {
    const StageTimer timer(&orb_times_, Stage::kOrbDetect);
    orb_.emplace(grey_, mask_, options_.orb);
  }
  if (!options_.parallel) return;
  if (line_worker) {
    coarse_levels_ = line_worker->submit([this] {
      const StageTimer timer(&coarse_times_, Stage::kOrbDetect);
      orb_->detectLevels(orb_->coarseLevelsStart(), orb_->levels());
    });
  }
  if (!options_.use_lines) return;
  if (line_worker) lines_ = line_worker->submit([this] { return runLines(); });
  else lines_ = std::async(std::launch::async, [this] { return runLines(); });
}

FeatureExtraction::~FeatureExtraction() {
  if (coarse_levels_.valid()) coarse_levels_.wait();
  if (lines_.valid()) lines_.wait();
}

FeatureExtraction::Lines FeatureExtraction::runLines() {
  Lines out;
  out.segments = detectLines(grey_, mask_, options_.lines, nullptr, &line_times_);
  const StageTimer timer(&line_times_, Stage::kLbd);
  out.descriptors = describeLines(grey_, out.segments, options_.lines);
  return out;
}

FrameFeatures FeatureExtraction::points(StageTimes* times) {
  FrameFeatures f;
  f.point_descriptors = cv::Mat(0, 32, CV_8U);
  f.line_descriptors = cv::Mat(0, 32, CV_8U);
  if (grey_.empty()) return f;
  {
    const StageTimer timer(times, Stage::kOrbDetect);
    orb_->detectLevels(0, coarse_levels_.valid() ? orb_->coarseLevelsStart() : orb_->levels());
  }
  if (coarse_levels_.valid()) coarse_levels_.get();
  if (times) {  // detection's time on both threads, without the wait
    times->add(orb_times_);
    times->add(coarse_times_);
  }
  std::vector<cv::KeyPoint> kps;
  orb_->finish(&kps, &f.point_descriptors, times);
  const StageTimer timer(times, Stage::kUndistort);
  f.points.reserve(kps.size());
  for (const cv::KeyPoint& k : kps) {
    Keypoint p;
    p.uv_raw = Eigen::Vector2d(k.pt.x, k.pt.y);
    p.uv = camera_.undistort(p.uv_raw);
    p.octave = k.octave;
    p.angle = k.angle;
    const float d = frame_.depth_m.empty() ? NAN : depthAt(frame_.depth_m, k.pt.x, k.pt.y);
    p.depth_m = std::isfinite(d) && d >= options_.min_depth_m ? d : NAN;
    f.points.push_back(p);
  }
  return f;
}

void FeatureExtraction::addLines(FrameFeatures* f, StageTimes* times) {
  if (grey_.empty() || !options_.use_lines) return;
  Lines lines = options_.parallel ? lines_.get() : runLines();
  if (times) times->add(line_times_);
  const StageTimer timer(times, Stage::kUndistort);
  f->line_descriptors = lines.descriptors;
  f->lines.reserve(lines.segments.size());
  for (const LineSegment2D& s : lines.segments) {
    Segment2D l;
    l.p_raw = s.p;
    l.q_raw = s.q;
    l.p = camera_.undistort(s.p);
    l.q = camera_.undistort(s.q);
    f->lines.push_back(l);
  }
}

FrameFeatures extractFeatures(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera,
                              const FeatureOptions& o, StageTimes* times) {
  FeatureExtraction extraction(frame, mask, camera, o);
  FrameFeatures f = extraction.points(times);
  extraction.addLines(&f, times);
  return f;
}

}  // namespace plslam
