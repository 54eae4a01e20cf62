// The SLAM map: keyframes, map points and 3D map lines, owned here in id-ordered
// containers; entities refer to each other by id. Feature observations of a frame are
// kept in the form every stage shares (FrameFeatures), in ideal (undistorted) pixels.
//
// Thread safety: Map itself is not synchronised; the pipeline holds `mutex()` while it
// reads or writes entities. Tracking writes too: it counts each landmark's `visible` and
// `found`, and makes every keyframe with the map points its depth gives; local mapping
// (observations, lines, culling, local BA) and the loop closer (corrections) write the rest.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/se3.h"
#include "core/time.h"

namespace plslam {

using Id = int64_t;
constexpr Id kNoId = -1;

/// A keypoint as the SLAM stages use it.
struct Keypoint {
  Eigen::Vector2d uv_raw;  ///< pixel in the raw (distorted) image
  Eigen::Vector2d uv;      ///< ideal (undistorted) pixel
  int octave = 0;          ///< pyramid level it was detected at
  float angle = 0;         ///< orientation, degrees (OpenCV convention)
  float depth_m = 0;       ///< depth at uv_raw, metres; NaN when the sensor gave none
};

/// A 2D line segment as the SLAM stages use it.
struct Segment2D {
  Eigen::Vector2d p_raw, q_raw;  ///< endpoints, raw pixels
  Eigen::Vector2d p, q;          ///< endpoints, ideal pixels
  int octave = 0;
};

/// Everything extracted from one image. Descriptors are CV_8U rows of 32 bytes (ORB, LBD).
struct FrameFeatures {
  std::vector<Keypoint> points;
  cv::Mat point_descriptors;
  std::vector<Segment2D> lines;
  cv::Mat line_descriptors;
};

/// A segmented object instance seen in a keyframe: semantic maps and loop closure use them.
struct KeyframeInstance {
  int class_id = -1;       ///< class index in the segmenter's class list (COCO: 0 person)
  std::string class_name;
  bool dynamic = false;    ///< judged moving in this keyframe (its pixels are kept out of the map)
  cv::Rect box;            ///< bounding box, image pixels
  int pixels = 0;          ///< mask area, pixels
  /// Median 3D position of its pixels with depth, in the keyframe's camera frame (NaN: no depth).
  Eigen::Vector3d centroid_c = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// One point of a keyframe's dense cloud, in the keyframe's camera frame (so a corrected
/// keyframe pose moves its cloud with it).
struct DensePoint {
  Eigen::Vector3f p_c = Eigen::Vector3f::Zero();
  uint8_t r = 0, g = 0, b = 0;
  int16_t class_id = -1;   ///< semantic class of the pixel (-1: no instance)
};

struct KeyFrame {
  Id id = kNoId;
  TimeNs t_ns = 0;
  SE3 T_w_c;
  FrameFeatures features;
  std::vector<Id> point_ids;  ///< per keypoint: the map point it observes, or kNoId
  std::vector<Id> line_ids;   ///< per line: the map line it observes, or kNoId
  cv::Mat dynamic_mask;       ///< CV_8U, 0 = pixels of moving objects (empty: no dynamic filtering)
  std::vector<KeyframeInstance> instances;  ///< segmented instances (empty without a segmenter)
  std::vector<DensePoint> dense;            ///< dense cloud, camera frame (empty until the dense stage made it)
};

struct MapPoint {
  Id id = kNoId;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  cv::Mat descriptor;           ///< the representative 32-byte descriptor (1 row)
  std::map<Id, int> observations;  ///< keyframe id -> keypoint index in that keyframe
  Id first_keyframe = kNoId;
  int visible = 1;  ///< times it was predicted inside a tracked frame
  int found = 1;    ///< times it was matched there
};

/// A 3D segment; its canonical state is the two world endpoints.
struct MapLine {
  Id id = kNoId;
  Eigen::Vector3d P_w = Eigen::Vector3d::Zero(), Q_w = Eigen::Vector3d::Zero();
  cv::Mat descriptor;
  std::map<Id, int> observations;  ///< keyframe id -> line index in that keyframe
  Id first_keyframe = kNoId;
  int visible = 1;
  int found = 1;
};

class Map {
 public:
  Map() = default;
  /// Moves the entities and id counters; the mutex is not moved (each map has its own).
  /// Neither map may be in use by another thread.
  Map(Map&& other) noexcept;
  Map& operator=(Map&& other) noexcept;

  std::mutex& mutex() const { return mutex_; }

  Id addKeyFrame(KeyFrame kf);
  Id addPoint(MapPoint p);
  Id addLine(MapLine l);
  /// Put back an entity with the id it already has (loading a saved map): ids and
  /// observations are kept as given, and later add*() calls get larger ids. Throws
  /// DataError on a negative or already used id. The caller restores both sides of every
  /// observation (mapfile checks them).
  Id restoreKeyFrame(KeyFrame kf);
  Id restorePoint(MapPoint p);
  Id restoreLine(MapLine l);
  /// Records that keypoint `index` of keyframe `kf` observes point `pt` (both sides).
  void addPointObservation(Id kf, int index, Id pt);
  void addLineObservation(Id kf, int index, Id line);
  /// Removes a landmark and every observation of it.
  void erasePoint(Id pt);
  void eraseLine(Id line);
  /// Moves landmark `from`'s observations to `into` and erases `from` (duplicates found
  /// by matching).
  void mergePoint(Id from, Id into);

  const std::map<Id, KeyFrame>& keyframes() const { return keyframes_; }
  const std::map<Id, MapPoint>& points() const { return points_; }
  const std::map<Id, MapLine>& lines() const { return lines_; }
  /// The entity with id `id`, or null (erased, never made, kNoId).
  KeyFrame* keyframe(Id id) { return byId(keyframe_at_, id); }
  MapPoint* point(Id id) { return byId(point_at_, id); }
  MapLine* line(Id id) { return byId(line_at_, id); }
  const KeyFrame* keyframe(Id id) const { return byId(keyframe_at_, id); }
  const MapPoint* point(Id id) const { return byId(point_at_, id); }
  const MapLine* line(Id id) const { return byId(line_at_, id); }

  /// Counts corrections of the whole map (loop closure). A stage that solved on a snapshot
  /// taken before a correction must not write its absolute result back over it.
  void noteCorrection() { ++corrections_; }
  uint64_t corrections() const { return corrections_; }

  /// Keyframes sharing at least `min_shared` map points with `kf`, most shared first.
  std::vector<std::pair<Id, int>> covisible(Id kf, int min_shared = 1) const;

 private:
  mutable std::mutex mutex_;
  std::map<Id, KeyFrame> keyframes_;
  std::map<Id, MapPoint> points_;
  std::map<Id, MapLine> lines_;
  // Each entity by id (null: erased or never made), so that keyframe(), point() and line()
  // are an array read rather than a walk down a tree scattered over the heap: the tracker
  // looks up thousands of landmarks a frame, and the walk got slower as the map grew
  // (docs/RESULTS.md, "The long run's growing search"). std::map nodes never move, so the
  // pointers hold until the entity is erased. Costs 8 bytes per id ever given out.
  std::vector<KeyFrame*> keyframe_at_;
  std::vector<MapPoint*> point_at_;
  std::vector<MapLine*> line_at_;
  template <typename T>
  static T* byId(const std::vector<T*>& at, Id id) {
    return id >= 0 && id < static_cast<Id>(at.size()) ? at[static_cast<size_t>(id)] : nullptr;
  }
  Id next_keyframe_id_ = 0, next_point_id_ = 0, next_line_id_ = 0;
  uint64_t corrections_ = 0;
};

}  // namespace plslam
