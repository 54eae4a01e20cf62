#include "frontend/feature_extraction.h"

#include <cmath>
#include <future>
#include <opencv2/imgproc.hpp>

namespace plslam {

void bindFeatureOptions(OptionTable* t, FeatureOptions* o) {
  t->bind("features.orb_features", &o->orb.num_features, "ORB keypoints per image");
  t->bind("features.orb_scale_factor", &o->orb.scale_factor, "ORB pyramid scale between levels");
  t->bind("features.orb_levels", &o->orb.num_levels, "ORB pyramid levels");
  t->bind("features.orb_fast_threshold", &o->orb.fast_threshold, "FAST threshold");
  t->bind("features.orb_min_fast_threshold", &o->orb.min_fast_threshold, "FAST threshold retried on weak images");
  t->bind("features.line_detect_scale", &o->lines.detect_scale, "LSD runs on the image resized by this");
  t->bind("features.line_min_length_ratio", &o->lines.min_length_ratio, "shortest segment, fraction of the image diagonal");
  t->bind("features.line_max", &o->lines.max_lines, "segments kept per image (the longest)");
  t->bind("features.line_merge_angle_deg", &o->lines.merge_angle_deg, "merge fragments closer than this in direction (deg)");
  t->bind("features.line_merge_distance_px", &o->lines.merge_distance_px, "merge fragments this close to each other's line (px)");
  t->bind("features.line_merge_gap_px", &o->lines.merge_gap_px, "merge fragments at most this far apart along the line (px)");
  t->bind("features.parallel", &o->parallel, "extract points and lines on two threads");
}

FrameFeatures extractFeatures(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera,
                              const FeatureOptions& o) {
  FrameFeatures f;
  f.point_descriptors = cv::Mat(0, 32, CV_8U);
  f.line_descriptors = cv::Mat(0, 32, CV_8U);
  if (frame.bgr.empty()) return f;
  cv::Mat grey;
  if (frame.bgr.channels() == 3) cv::cvtColor(frame.bgr, grey, cv::COLOR_BGR2GRAY);
  else grey = frame.bgr;

  auto lines_job = [&] {
    std::vector<LineSegment2D> segs = detectLines(grey, mask, o.lines);
    return std::make_pair(segs, describeLines(grey, segs, o.lines));
  };
  std::future<std::pair<std::vector<LineSegment2D>, cv::Mat>> lines_future;
  if (o.use_lines && o.parallel) lines_future = std::async(std::launch::async, lines_job);

  std::vector<cv::KeyPoint> kps;
  extractOrb(grey, mask, o.orb, &kps, &f.point_descriptors);
  f.points.reserve(kps.size());
  for (const cv::KeyPoint& k : kps) {
    Keypoint p;
    p.uv_raw = Eigen::Vector2d(k.pt.x, k.pt.y);
    p.uv = camera.undistort(p.uv_raw);
    p.octave = k.octave;
    p.angle = k.angle;
    const float d = frame.depth_m.empty() ? NAN : depthAt(frame.depth_m, k.pt.x, k.pt.y);
    p.depth_m = std::isfinite(d) && d >= o.min_depth_m ? d : NAN;
    f.points.push_back(p);
  }

  if (o.use_lines) {
    auto [segs, desc] = o.parallel ? lines_future.get() : lines_job();
    f.line_descriptors = desc;
    f.lines.reserve(segs.size());
    for (const LineSegment2D& s : segs) {
      Segment2D l;
      l.p_raw = s.p;
      l.q_raw = s.q;
      l.p = camera.undistort(s.p);
      l.q = camera.undistort(s.q);
      f.lines.push_back(l);
    }
  }
  return f;
}

}  // namespace plslam
