// Matching binary descriptors (ORB, LBD: 32 bytes, Hamming distance):
//  - by descriptor alone: brute force with Lowe's ratio, a mutual check and an optional
//    rotation-consistency histogram (initialisation, relocalisation, loop candidates);
//  - by projection: each landmark has a predicted position (and octave) in the frame;
//    candidate keypoints come from a grid around it, candidate segments are gated by
//    direction, distance and overlap; the closest descriptor wins.
// Positions are whatever the caller uses consistently (the tracker: ideal pixels).
// Results are index pairs: query = prediction / query row, train = frame feature / train row.
//
// Stateless and deterministic. Thread safety: every function may be called concurrently.
#pragma once

#include <string>
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "features/line_extractor.h"

namespace plslam {

class OptionTable;

/// Hamming distance of two 32-byte descriptors (0..256).
int hammingDistance(const uint8_t* a, const uint8_t* b);

struct DescriptorMatch {
  int query = -1;    ///< query row / prediction index
  int train = -1;    ///< train row / frame feature index
  int distance = 0;  ///< Hamming distance, bits
};

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindBruteForceOptions (features/matching.cpp). `plslam run --print-config` lists them.
struct BruteForceOptions {
  int max_distance = 64;
  float ratio = 0.8f;
  bool mutual = true;
};

/// Binds `prefix` + "max_distance", "ratio", "mutual".
void bindBruteForceOptions(OptionTable* table, const std::string& prefix, BruteForceOptions* options);

/// Every query row against every train row (CV_8U, 32 columns). Each train row is used at
/// most once (the closest query keeps it). Sorted by query index.
std::vector<DescriptorMatch> matchBruteForce(const cv::Mat& query, const cv::Mat& train, const BruteForceOptions& options);

struct OrientationOptions {
  int bins = 30;               ///< histogram bins over 360 degrees
  int keep_bins = 3;           ///< the most populated bins are kept...
  float min_bin_ratio = 0.1f;  ///< ...all but the first only when they hold this fraction of the first
};

/// Rotation consistency (as in ORB-SLAM): a histogram of angle(train) - angle(query) over
/// the matches; keeps the matches that fall in the dominant bins. Angles in degrees (cv::KeyPoint
/// convention), indexed by the matches' query and train. Keeps the input order.
std::vector<DescriptorMatch> filterByOrientation(const std::vector<DescriptorMatch>& matches,
                                                 const std::vector<float>& query_angles_deg,
                                                 const std::vector<float>& train_angles_deg,
                                                 const OrientationOptions& options = {});

/// A uniform grid over 2D positions for radius queries. Positions outside
/// [0, width) x [0, height) go to the border cells, so none is lost.
class PointGrid {
 public:
  PointGrid() = default;
  PointGrid(std::vector<Eigen::Vector2d> points, int width, int height, int cell_size = 16);
  /// Indices of the points within `radius` of `centre` (Euclidean), cell by cell: not sorted
  /// (the matchers' choices do not depend on the order).
  void query(const Eigen::Vector2d& centre, double radius, std::vector<int>* out) const;
  const std::vector<Eigen::Vector2d>& points() const { return points_; }
  size_t size() const { return points_.size(); }

 private:
  std::vector<Eigen::Vector2d> points_;
  int cols_ = 0, rows_ = 0, cell_ = 16;
  std::vector<int> start_;  ///< cell c holds order_[start_[c] .. start_[c + 1])
  std::vector<int> order_;
  std::vector<Eigen::Vector2d> cell_points_;  ///< points_[order_[k]]: a query reads them in a row
};

/// Where a landmark point should appear in the frame.
struct PointPrediction {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< predicted position
  int octave = -1;  ///< predicted pyramid level; -1 = unknown (any level, level-0 radius)
};

struct PointProjectionOptions {
  double radius_px = 10;              ///< search radius at level 0 around the prediction
  double octave_radius_factor = 1.2;  ///< radius *= this^predicted octave (use the ORB scale factor)
  int octave_window = 1;              ///< with a predicted octave: candidates within +-this many levels (-1: any)
  int max_distance = 64;              ///< Hamming distance accepted
  float ratio = 0.9f;                 ///< best < ratio * second best (1 disables)
};

/// For each prediction (row i of `prediction_descriptors`), the closest keypoint of the
/// frame within the radius. `grid` holds the frame's keypoint positions; `octaves` their
/// levels (empty: levels are not checked); `descriptors` their rows. Keypoints with
/// excluded[k] != 0 are skipped (`excluded` may be empty). Each keypoint goes to at most
/// one prediction (the closest descriptor). Sorted by prediction index.
std::vector<DescriptorMatch> matchPointsByProjection(const std::vector<PointPrediction>& predictions,
                                                     const cv::Mat& prediction_descriptors, const PointGrid& grid,
                                                     const std::vector<int>& octaves, const cv::Mat& descriptors,
                                                     const PointProjectionOptions& options,
                                                     const std::vector<char>& excluded = {});

struct LineProjectionOptions {
  double angle_deg = 8;        ///< max direction difference (modulo 180 degrees)
  double distance_px = 8;      ///< max distance of the segment's midpoint to the predicted infinite line
  double min_overlap = 0.1;    ///< overlap along the predicted line / the shorter of the two lengths
  double min_length_px = 5;    ///< predictions shorter than this are not searched
  int max_distance = 80;       ///< LBD Hamming distance accepted
  float ratio = 0.9f;          ///< best < ratio * second best (1 disables)
};

/// For each predicted segment (endpoints in the order the landmark was described in, row i
/// of `prediction_descriptors`), the closest segment of `lines` (rows of `descriptors`)
/// that passes the geometric gates. Same rules as matchPointsByProjection.
std::vector<DescriptorMatch> matchLinesByProjection(const std::vector<LineSegment2D>& predictions,
                                                    const cv::Mat& prediction_descriptors,
                                                    const std::vector<LineSegment2D>& lines, const cv::Mat& descriptors,
                                                    const LineProjectionOptions& options,
                                                    const std::vector<char>& excluded = {});

}  // namespace plslam
