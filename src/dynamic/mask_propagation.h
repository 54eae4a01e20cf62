// Carries instance masks from the image they were segmented on to a later image. A segmenter
// slower than the camera delivers masks of an earlier frame, and a walker has moved on since:
// used where they were, the masks miss the walker's leading side and cover background.
//
// Per instance: corners inside its mask (eroded, so that their patches see the instance and
// not the background behind its outline) are tracked into the later image with pyramidal
// Lucas-Kanade, frame by frame through the images in between when they are given (a person
// near the camera moves tens of pixels a frame: single steps are followed far more reliably
// than several at once). The instance's pixels move by the median displacement of its
// corners: it follows the camera's motion and the object's own, and neither a walker's
// swinging limbs nor a few lost corners pull it (on the walkers of the crowded synthetic
// scene, a similarity fitted to the corners, extrapolated from the parts that have corners to
// the whole outline, covered them less well, and a forward-backward check of each corner
// added the cost of a second tracking pass and nothing to the cover). An instance with too
// few tracked corners stays where it was. One cut by the image border goes on beyond it:
// moving inward, the part that came into view is filled in from its border pixels.
//
// Deterministic (the same images give the same masks). The functions are stateless and
// thread-safe; a MaskCarrier is used from one thread.
#pragma once

#include <string>
#include <deque>
#include <opencv2/core.hpp>
#include <vector>

#include "dynamic/instance.h"

namespace plslam {

class OptionTable;

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindMaskPropagationOptions (dynamic/option_keys.cpp). `plslam run --print-config` lists them.
struct MaskPropagationOptions {
  int max_corners = 30;
  double corner_quality = 0.01;
  int corner_distance_px = 5;
  int erode_px = 5;
  int window_px = 15;
  int pyramid_levels = 3;
  int min_corners = 3;
  // A carried outline is uncertain in proportion to how far it was carried.
  double interior_margin_fraction = 0.25;
  int max_interior_margin_px = 30;
};

/// Binds `prefix` + "max_corners", "window_px", ...
void bindMaskPropagationOptions(OptionTable* table, const std::string& prefix, MaskPropagationOptions* options);

/// A segmentation with what carrying it needs from its image, prepared once per segmentation.
struct PropagationSource {
  Segmentation segmentation;
  std::vector<cv::Mat> pyramid;                   ///< of the segmented image (empty: not prepared)
  std::vector<std::vector<cv::Point2f>> corners;  ///< per instance, same order
};

/// Prepares `segmentation` of `bgr` (CV_8UC3, the image it was computed on).
PropagationSource preparePropagation(Segmentation segmentation, const cv::Mat& bgr, const MaskPropagationOptions& options);

/// The image pyramid the propagation tracks into (build it once per target image).
std::vector<cv::Mat> propagationPyramid(const cv::Mat& bgr, const MaskPropagationOptions& options);

struct PropagationStats {
  int moved = 0;  ///< instances moved by their corners
  int kept = 0;   ///< left where they were (too few corners tracked)
  std::vector<cv::Point> shifts;  ///< per instance, how far it was moved (pixels)
};

/// Where a source's corners are in a later image.
struct PropagationTrack {
  std::vector<std::vector<cv::Point2f>> from;  ///< per instance: the corners still tracked, in the segmented image
  std::vector<std::vector<cv::Point2f>> at;    ///< ... and where they are now
};

/// A track at the segmented image itself.
PropagationTrack startTrack(const PropagationSource& source);
/// Moves the track's corners from the image of pyramid `previous` to that of `next`; corners
/// lost on the way are dropped.
void advanceTrack(PropagationTrack* track, const std::vector<cv::Mat>& previous, const std::vector<cv::Mat>& next,
                  const MaskPropagationOptions& options);
/// The source's segmentation moved to where `track` is: same instances, ids and t_ns (the
/// stamp of the segmented image), moved pixels and boxes.
Segmentation moveSegmentation(const PropagationSource& source, const PropagationTrack& track,
                              const MaskPropagationOptions& options, PropagationStats* stats = nullptr);

/// The source's segmentation carried into the image of `target_pyramid` in one step.
Segmentation propagateSegmentation(const PropagationSource& source, const std::vector<cv::Mat>& target_pyramid,
                                   const MaskPropagationOptions& options, PropagationStats* stats = nullptr);

/// The instances of a carried segmentation shrunk by their margins (interior_margin_*), as a
/// label image like `carried.instance_ids`: the pixels surely on each instance.
cv::Mat carriedInteriors(const Segmentation& carried, const PropagationStats& stats, const MaskPropagationOptions& options);

/// Carries the newest segmentation to each new frame, through the frames in between.
class MaskCarrier {
 public:
  /// Keeps at most `max_frames` frames (a pyramid is a few MB): a source older than that jumps
  /// to the oldest one kept in one step.
  explicit MaskCarrier(MaskPropagationOptions options = {}, int max_frames = 16);
  /// The next frame (numbers increase). Its grey image is kept while a later source may
  /// need it; its pyramid is built only when a track goes through it.
  void addFrame(int frame, const cv::Mat& bgr);
  /// A newer segmentation, of frame `frame` (a frame added before, or the newest one).
  void setSource(PropagationSource source, int frame);
  /// The source's segmentation carried into the newest frame added (as it is without a source).
  Segmentation carry(PropagationStats* stats = nullptr);

 private:
  struct Kept {
    int frame = -1;
    cv::Mat grey;
    std::vector<cv::Mat> pyramid;  // built on first use
  };
  MaskPropagationOptions options_;
  size_t max_frames_;
  std::deque<Kept> frames_;  // oldest first, all after the source's frame
  PropagationSource source_;
  PropagationTrack track_;
  int track_frame_ = -1;             // the frame track_ is at
  std::vector<cv::Mat> track_pyramid_;  // that frame's pyramid
};

}  // namespace plslam
