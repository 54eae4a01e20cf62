#include "dynamic/mask_propagation.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {

cv::Mat grey(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw DataError(str("mask propagation: the image is ", bgr.empty() ? "empty" : "not CV_8UC3"));
  cv::Mat g;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  return g;
}

cv::Rect clipped(const cv::Rect& r, cv::Size size) { return r & cv::Rect(cv::Point(0, 0), size); }

std::vector<cv::Point2f> instanceCorners(const cv::Mat& grey_image, const Segmentation& s, const Instance& inst,
                                         const MaskPropagationOptions& o) {
  const cv::Rect roi = clipped(inst.box, grey_image.size());
  std::vector<cv::Point2f> corners;
  if (roi.empty()) return corners;
  cv::Mat inside = s.instance_ids(roi) == inst.id;
  cv::Mat eroded;
  const int k = 2 * std::max(0, o.erode_px) + 1;
  // Outside the box is outside the instance (erode's default border would count it inside).
  cv::erode(inside, eroded, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)), cv::Point(-1, -1), 1,
            cv::BORDER_CONSTANT, cv::Scalar(0));
  // A thin instance has no pixel that far inside: its own pixels are better than nothing.
  if (cv::countNonZero(eroded) == 0) eroded = inside;
  cv::goodFeaturesToTrack(grey_image(roi), corners, o.max_corners, o.corner_quality, o.corner_distance_px, eroded);
  for (cv::Point2f& c : corners) c += cv::Point2f(static_cast<float>(roi.x), static_cast<float>(roi.y));
  return corners;
}

float median(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The shift of one instance, whole pixels: the median displacement of its corners, none
// when too few were tracked.
cv::Point instanceShift(const std::vector<cv::Point2f>& from, const std::vector<cv::Point2f>& to,
                        const MaskPropagationOptions& o, PropagationStats* stats) {
  if (static_cast<int>(from.size()) < std::max(1, o.min_corners)) {
    ++stats->kept;
    return {0, 0};
  }
  std::vector<float> dx, dy;
  for (size_t i = 0; i < from.size(); ++i) {
    dx.push_back(to[i].x - from[i].x);
    dy.push_back(to[i].y - from[i].y);
  }
  ++stats->moved;
  return {static_cast<int>(std::lround(median(dx))), static_cast<int>(std::lround(median(dy)))};
}

// Draws the instance's pixels of `src` shifted into `out`; returns their new box. An instance
// cut by the image border goes on beyond it: moving inward, the part that has come into view
// is filled in by repeating its pixels at the border.
cv::Rect shiftInstance(const Segmentation& src, const Instance& inst, cv::Point shift, cv::Mat* out) {
  const cv::Size size = src.instance_ids.size();
  const cv::Rect box = clipped(inst.box, size);
  if (box.empty()) return {};
  cv::Rect dst = box + shift;
  if (box.x == 0 && shift.x > 0) dst.x = 0, dst.width += shift.x;
  if (box.y == 0 && shift.y > 0) dst.y = 0, dst.height += shift.y;
  if (box.br().x == size.width && shift.x < 0) dst.width -= shift.x;
  if (box.br().y == size.height && shift.y < 0) dst.height -= shift.y;
  dst = clipped(dst, size);
  if (dst.empty()) return {};
  // Pixel p of `dst` shows source pixel p - shift; outside the box only in the filled-in strips,
  // which BORDER_REPLICATE fills with the box's (= the image's) border pixels.
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, box.x + shift.x - dst.x, 0, 1, box.y + shift.y - dst.y);
  const cv::Mat inside = src.instance_ids(box) == inst.id;
  cv::Mat moved;
  cv::warpAffine(inside, moved, m, dst.size(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  (*out)(dst).setTo(cv::Scalar(inst.id), moved);
  const cv::Rect drawn = cv::boundingRect(moved);
  return drawn.empty() ? cv::Rect() : drawn + dst.tl();
}

std::vector<cv::Mat> pyramidOfGrey(const cv::Mat& g, const MaskPropagationOptions& o) {
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(g, pyramid, cv::Size(o.window_px, o.window_px), o.pyramid_levels);
  return pyramid;
}

}  // namespace

std::vector<cv::Mat> propagationPyramid(const cv::Mat& bgr, const MaskPropagationOptions& o) {
  return pyramidOfGrey(grey(bgr), o);
}

PropagationSource preparePropagation(Segmentation s, const cv::Mat& bgr, const MaskPropagationOptions& o) {
  PropagationSource out;
  if (!s.empty() && !s.instances.empty()) {
    const cv::Mat g = grey(bgr);
    if (g.size() != s.instance_ids.size()) throw DataError("mask propagation: the masks and the image differ in size");
    out.pyramid = pyramidOfGrey(g, o);
    for (const Instance& inst : s.instances) out.corners.push_back(instanceCorners(g, s, inst, o));
  }
  out.segmentation = std::move(s);
  return out;
}

PropagationTrack startTrack(const PropagationSource& source) { return {source.corners, source.corners}; }

void advanceTrack(PropagationTrack* t, const std::vector<cv::Mat>& previous, const std::vector<cv::Mat>& next,
                  const MaskPropagationOptions& o) {
  std::vector<cv::Point2f> now;
  for (const auto& c : t->at) now.insert(now.end(), c.begin(), c.end());
  if (now.empty()) return;
  std::vector<cv::Point2f> to;
  std::vector<uint8_t> found;
  std::vector<float> err;
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(previous, next, now, to, found, err, cv::Size(o.window_px, o.window_px), o.pyramid_levels, stop);
  size_t i = 0;
  for (size_t k = 0; k < t->at.size(); ++k) {
    std::vector<cv::Point2f> from, at;
    for (size_t j = 0; j < t->at[k].size(); ++j, ++i) {
      if (!found[i]) continue;
      from.push_back(t->from[k][j]);
      at.push_back(to[i]);
    }
    t->from[k] = std::move(from);
    t->at[k] = std::move(at);
  }
}

Segmentation moveSegmentation(const PropagationSource& src, const PropagationTrack& track,
                              const MaskPropagationOptions& o, PropagationStats* stats) {
  PropagationStats local_stats;
  if (!stats) stats = &local_stats;
  const Segmentation& s = src.segmentation;
  if (s.instances.empty() || track.from.size() != s.instances.size()) return s;
  Segmentation out = s;
  // A new image: assigning Mat::zeros would write into the buffer `out` shares with the source.
  out.instance_ids = cv::Mat(s.instance_ids.size(), CV_16UC1, cv::Scalar(0));
  for (size_t k = 0; k < s.instances.size(); ++k) {
    const cv::Point shift = instanceShift(track.from[k], track.at[k], o, stats);
    stats->shifts.push_back(shift);
    out.instances[k].box = shiftInstance(s, s.instances[k], shift, &out.instance_ids);
  }
  return out;
}

Segmentation propagateSegmentation(const PropagationSource& src, const std::vector<cv::Mat>& target,
                                   const MaskPropagationOptions& o, PropagationStats* stats) {
  if (src.pyramid.empty() || target.empty()) return src.segmentation;
  if (target[0].size() != src.segmentation.instance_ids.size())
    throw DataError("mask propagation: the target image and the masks differ in size");
  PropagationTrack track = startTrack(src);
  advanceTrack(&track, src.pyramid, target, o);
  return moveSegmentation(src, track, o, stats);
}

cv::Mat carriedInteriors(const Segmentation& carried, const PropagationStats& stats, const MaskPropagationOptions& o) {
  cv::Mat out(carried.instance_ids.size(), CV_16UC1, cv::Scalar(0));
  for (size_t k = 0; k < carried.instances.size(); ++k) {
    const Instance& inst = carried.instances[k];
    const cv::Rect box = clipped(inst.box, out.size());
    if (box.empty()) continue;
    const double carried_px = k < stats.shifts.size() ? cv::norm(stats.shifts[k]) : 0.0;
    const int margin = std::min(o.max_interior_margin_px, static_cast<int>(std::lround(o.interior_margin_fraction * carried_px)));
    cv::Mat inside = carried.instance_ids(box) == inst.id;
    if (margin > 0) {  // a distance transform: an erosion by a disc this large costs milliseconds
      cv::Mat padded, distance;
      cv::copyMakeBorder(inside, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
      cv::distanceTransform(padded, distance, cv::DIST_L2, cv::DIST_MASK_3);
      inside = distance(cv::Rect(1, 1, box.width, box.height)) > margin;
    }
    out(box).setTo(cv::Scalar(inst.id), inside);
  }
  return out;
}

MaskCarrier::MaskCarrier(MaskPropagationOptions options, int max_frames)
    : options_(options), max_frames_(static_cast<size_t>(std::max(1, max_frames))) {}

void MaskCarrier::addFrame(int frame, const cv::Mat& bgr) {
  frames_.push_back({frame, grey(bgr), {}});
  while (frames_.size() > max_frames_) frames_.pop_front();  // a track jumps over the frames dropped
}

void MaskCarrier::setSource(PropagationSource source, int frame) {
  // Later sources are of later frames: the frames up to this one are not needed any more.
  while (!frames_.empty() && frames_.front().frame <= frame) frames_.pop_front();
  source_ = std::move(source);
  track_ = startTrack(source_);
  track_frame_ = frame;
  track_pyramid_ = source_.pyramid;
}

Segmentation MaskCarrier::carry(PropagationStats* stats) {
  if (source_.pyramid.empty()) return source_.segmentation;
  for (Kept& k : frames_) {
    if (k.frame <= track_frame_) continue;
    if (k.pyramid.empty()) k.pyramid = pyramidOfGrey(k.grey, options_);
    advanceTrack(&track_, track_pyramid_, k.pyramid, options_);
    track_frame_ = k.frame;
    track_pyramid_ = k.pyramid;
  }
  return moveSegmentation(source_, track_, options_, stats);
}

}  // namespace plslam
