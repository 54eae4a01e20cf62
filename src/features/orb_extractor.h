// ORB keypoints spread over the image, with a mask that forbids regions.
//
// FAST corners on a scale pyramid (with a lower threshold in the cells where the normal one
// finds nothing), a quadtree per level that keeps the strongest corner of each node so the
// points cover the textured parts evenly (ORB-SLAM's distribution), the intensity-centroid
// orientation, and OpenCV's rBRIEF descriptors (cv::ORB's learned pattern, 32 bytes).
//
// Stateless and deterministic: the same image and mask give the same output.
// Thread safety: every function may be called concurrently.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "core/profile.h"

namespace plslam {

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindFeatureOptions (frontend/feature_extraction.cpp). `plslam run --print-config` lists them.
struct OrbOptions {
  int num_features = 1000;
  float scale_factor = 1.2f;
  int num_levels = 8;
  int fast_threshold = 20;
  int min_fast_threshold = 7;
  int cell_size = 32;

  /// Throws ConfigError when a value is out of range.
  void validate() const;
};

/// Keypoints lie at least this far (in their own level's pixels) from the level border,
/// so that the 31x31 orientation and descriptor patch fits in the image.
constexpr int kOrbEdge = 16;

/// Detects and describes ORB keypoints.
/// `image`: CV_8UC1, CV_8UC3 (BGR) or CV_8UC4 (BGRA). `mask`: empty (everything allowed) or
/// CV_8UC1 of the image size; no keypoint lies on a pixel where it is 0 (the keypoint's
/// level-0 position, rounded).
/// Output keypoints: raw pixels at level 0, octave = pyramid level, angle in degrees
/// [0, 360), response = FAST score, size = 31 * scale of the level; sorted by octave.
/// Descriptors: CV_8U, one 32-byte row per keypoint (0 rows when there are none).
/// An empty, tiny or textureless image gives no keypoints.
/// Throws DataError for an unsupported image type or a mask of the wrong size or type,
/// ConfigError for invalid options. `times` (optional) gets the kOrbDetect and kOrbDescribe stages.
void extractOrb(const cv::Mat& image, const cv::Mat& mask, const OrbOptions& options, std::vector<cv::KeyPoint>* keypoints,
                cv::Mat* descriptors, StageTimes* times = nullptr);

/// extractOrb in steps, so that the FAST corners of the coarser pyramid levels can be found
/// on another thread while the caller's finds those of the finer ones. The result is
/// extractOrb's, whatever runs where:
///
///     OrbExtraction orb(image, mask, options);                // grey image, mask check, pyramid
///     orb.detectLevels(orb.coarseLevelsStart(), orb.levels());  // e.g. on another thread
///     orb.detectLevels(0, orb.coarseLevelsStart());
///     orb.finish(&keypoints, &descriptors);                     // after both
///
/// detectLevels() on disjoint ranges may run concurrently; everything else on one thread.
class OrbExtraction {
 public:
  /// A FAST corner of one level, in that level's pixels.
  struct Candidate {
    int x, y;
    float response;
  };

  /// Throws as extractOrb does.
  OrbExtraction(const cv::Mat& image, const cv::Mat& mask, const OrbOptions& options);
  /// Pyramid levels to detect on (0 for an empty or tiny image, or no features wanted).
  int levels() const { return static_cast<int>(pyramid_.size()); }
  /// The first of the coarser levels that together hold at most half of the pyramid's pixels.
  int coarseLevelsStart() const;
  /// FAST corners of levels [first, last).
  void detectLevels(int first, int last);
  /// Spreads, orients and describes the corners of every level; `times` as extractOrb's.
  void finish(std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors, StageTimes* times = nullptr);

 private:
  OrbOptions options_;
  cv::Mat grey_, mask_;
  std::vector<float> scales_;
  std::vector<cv::Mat> pyramid_;
  std::vector<std::vector<Candidate>> candidates_;  // per level
};

/// scale_factor^level for level 0..num_levels-1: level pixels times this = level-0 pixels.
std::vector<float> orbLevelScales(const OrbOptions& options);

/// Grey view of `image` (shared data when it is CV_8UC1 already, converted from BGR/BGRA
/// otherwise); throws DataError for other types. Used by the point and line extractors.
cv::Mat toGrey(const cv::Mat& image);
/// Throws DataError unless `mask` is empty or CV_8UC1 of `size`.
void checkMask(const cv::Mat& mask, const cv::Size& size);

}  // namespace plslam
