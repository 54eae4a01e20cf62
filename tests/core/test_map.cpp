#include <gtest/gtest.h>

#include "core/map.h"

using namespace plslam;

namespace {
KeyFrame keyframeWith(int points, int lines) {
  KeyFrame kf;
  kf.features.points.resize(points);
  kf.features.lines.resize(lines);
  return kf;
}
}  // namespace

TEST(Map, ObservationsAreKeptOnBothSides) {
  Map map;
  const Id a = map.addKeyFrame(keyframeWith(5, 2));
  const Id b = map.addKeyFrame(keyframeWith(5, 2));
  const Id p = map.addPoint(MapPoint{});
  map.addPointObservation(a, 1, p);
  map.addPointObservation(b, 3, p);
  EXPECT_EQ(map.point(p)->observations.size(), 2u);
  EXPECT_EQ(map.keyframe(a)->point_ids[1], p);
  // Re-observing the point from another keypoint of the same keyframe moves it.
  map.addPointObservation(a, 4, p);
  EXPECT_EQ(map.keyframe(a)->point_ids[1], kNoId);
  EXPECT_EQ(map.keyframe(a)->point_ids[4], p);
  EXPECT_EQ(map.point(p)->observations.at(a), 4);
  map.erasePoint(p);
  EXPECT_EQ(map.point(p), nullptr);
  EXPECT_EQ(map.keyframe(a)->point_ids[4], kNoId);
  EXPECT_EQ(map.keyframe(b)->point_ids[3], kNoId);
}

TEST(Map, CovisibilityCountsSharedPoints) {
  Map map;
  const Id a = map.addKeyFrame(keyframeWith(10, 0));
  const Id b = map.addKeyFrame(keyframeWith(10, 0));
  const Id c = map.addKeyFrame(keyframeWith(10, 0));
  for (int i = 0; i < 6; ++i) {
    const Id p = map.addPoint(MapPoint{});
    map.addPointObservation(a, i, p);
    map.addPointObservation(i < 4 ? b : c, i, p);
  }
  const auto cov = map.covisible(a);
  ASSERT_EQ(cov.size(), 2u);
  EXPECT_EQ(cov[0], std::make_pair(b, 4));
  EXPECT_EQ(cov[1], std::make_pair(c, 2));
  EXPECT_EQ(map.covisible(a, 3).size(), 1u);
}

TEST(Map, MergeMovesObservations) {
  Map map;
  const Id a = map.addKeyFrame(keyframeWith(3, 0));
  const Id b = map.addKeyFrame(keyframeWith(3, 0));
  const Id p = map.addPoint(MapPoint{});
  const Id q = map.addPoint(MapPoint{});
  map.addPointObservation(a, 0, p);
  map.addPointObservation(b, 2, q);
  map.mergePoint(q, p);
  EXPECT_EQ(map.point(q), nullptr);
  EXPECT_EQ(map.point(p)->observations.size(), 2u);
  EXPECT_EQ(map.keyframe(b)->point_ids[2], p);
}

TEST(Map, LookupByIdFindsEachEntityThroughAddEraseRestoreAndMove) {
  Map map;
  std::vector<Id> points;
  for (int k = 0; k < 100; ++k) {
    MapPoint p;
    p.p_w = Eigen::Vector3d(k, 0, 0);
    points.push_back(map.addPoint(p));
  }
  const Id line = map.addLine(MapLine{});
  for (int k = 0; k < 100; k += 3) map.erasePoint(points[k]);
  for (int k = 0; k < 100; ++k) {
    const MapPoint* p = map.point(points[k]);
    if (k % 3 == 0) {
      EXPECT_EQ(p, nullptr) << "erased point " << k;
    } else {
      ASSERT_NE(p, nullptr) << "point " << k;
      EXPECT_EQ(p->id, points[k]);
      EXPECT_EQ(p->p_w.x(), k);  // its own data, not a neighbour's
    }
  }
  EXPECT_EQ(map.point(kNoId), nullptr);
  EXPECT_EQ(map.point(points.back() + 1), nullptr);  // never made
  EXPECT_EQ(map.keyframe(0), nullptr);

  // A saved point put back under its own id, far beyond the ids made so far.
  MapPoint far;
  far.id = 5000;
  map.restorePoint(far);
  ASSERT_NE(map.point(5000), nullptr);
  EXPECT_EQ(map.point(5000)->id, 5000);
  EXPECT_EQ(map.addPoint(MapPoint{}), 5001);

  // Moved maps keep their lookups; the emptied one finds nothing.
  Map moved(std::move(map));
  ASSERT_NE(moved.point(points[1]), nullptr);
  EXPECT_EQ(moved.point(points[1])->p_w.x(), 1);
  EXPECT_NE(moved.line(line), nullptr);
  EXPECT_EQ(map.point(points[1]), nullptr);  // NOLINT(bugprone-use-after-move): moved-from is documented empty
  EXPECT_EQ(map.line(line), nullptr);
}
