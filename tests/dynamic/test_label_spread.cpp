// Motion labels spread over the Delaunay graph of all keypoints (label_spread.h), on grids
// of features whose true labels are known.
#include <gtest/gtest.h>

#include <limits>

#include "core/error.h"
#include "dynamic/label_spread.h"

namespace plslam {
namespace {

const cv::Size kImage(640, 480);

struct Layout {
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> depth;
  std::vector<int8_t> labels;
  std::vector<int> object;  // 1: on the near object
};

// A wall at 3 m filling the image (grid every 40 px) and a near object at 1.5 m in the
// square [205, 345]^2 (grid every 20 px, offset so no pixel is shared). Wall features are
// judged still, but for the ring right around the object (unjudged); of the object's
// features every other column is judged moving, the rest unjudged.
Layout wallAndObject() {
  Layout l;
  for (int v = 20; v < 480; v += 40)
    for (int u = 20; u < 640; u += 40) {
      if (u > 190 && u < 370 && v > 190 && v < 370) continue;  // hidden by the object
      l.uv.emplace_back(u, v);
      l.depth.push_back(3.0);
      const bool ring = u >= 180 && u <= 380 && v >= 180 && v <= 380;
      l.labels.push_back(ring ? -1 : 0);
      l.object.push_back(0);
    }
  int k = 0;
  for (int v = 205; v <= 345; v += 20)
    for (int u = 205; u <= 345; u += 20, ++k) {
      l.uv.emplace_back(u, v);
      l.depth.push_back(1.5 + 0.01 * (k % 3));
      l.labels.push_back(k % 2 ? 1 : -1);
      l.object.push_back(1);
    }
  return l;
}

TEST(LabelSpread, UnjudgedFeaturesOnAMovingObjectBecomeMovingAndTheWallStaysStill) {
  const Layout l = wallAndObject();
  const LabelSpreadResult r = spreadMotionLabels(buildSurfaceGraph(l.uv, l.depth, kImage), l.labels);
  ASSERT_EQ(r.labels.size(), l.labels.size());
  int object_moving = 0, object_total = 0;
  for (size_t i = 0; i < l.labels.size(); ++i) {
    if (l.object[i]) {
      ++object_total;
      object_moving += r.labels[i] == 1;
    } else {
      EXPECT_EQ(r.labels[i], 0) << "wall feature " << i << " must stay still (the depth step cuts the edges)";
    }
  }
  EXPECT_EQ(object_moving, object_total);
  EXPECT_GT(r.spread_moving, 0);
  EXPECT_EQ(r.isolated_cleared, 0) << "moving features with moving neighbours are no mismatches";
}

TEST(LabelSpread, WithoutTheDepthStepMovingLabelsWouldLeakOntoTheWall) {
  // The object flattened onto the wall: edges now join the two, and the unjudged ring of wall
  // features takes the object's label in places. This is what the depth test prevents.
  Layout l = wallAndObject();
  for (double& z : l.depth) z = 3.0;
  const LabelSpreadResult r = spreadMotionLabels(buildSurfaceGraph(l.uv, l.depth, kImage), l.labels);
  int ring_moving = 0;
  for (size_t i = 0; i < l.labels.size(); ++i) ring_moving += !l.object[i] && r.labels[i] == 1;
  EXPECT_GT(ring_moving, 0);
}

TEST(LabelSpread, AnIsolatedMovingFeatureAmongStillOnesIsAMismatch) {
  Layout l = wallAndObject();
  // One wall feature far from the object flagged moving.
  size_t lone = 0;
  for (size_t i = 0; i < l.uv.size(); ++i)
    if (!l.object[i] && l.uv[i].x() == 540 && l.uv[i].y() == 100) lone = i;
  ASSERT_EQ(l.uv[lone], Eigen::Vector2d(540, 100));
  l.labels[lone] = 1;
  const LabelSpreadResult r = spreadMotionLabels(buildSurfaceGraph(l.uv, l.depth, kImage), l.labels);
  EXPECT_EQ(r.labels[lone], 0);
  EXPECT_EQ(r.isolated_cleared, 1);
}

TEST(LabelSpread, TheMovingAreaIsTheObjectsTriangles) {
  const Layout l = wallAndObject();
  const LabelSpreadResult r = spreadMotionLabels(buildSurfaceGraph(l.uv, l.depth, kImage), l.labels);
  ASSERT_FALSE(r.moving_triangles.empty());
  double area = 0;
  for (const auto& t : r.moving_triangles) {
    for (const cv::Point2f& p : t) {
      EXPECT_GE(p.x, 205);
      EXPECT_LE(p.x, 345);
      EXPECT_GE(p.y, 205);
      EXPECT_LE(p.y, 345);
    }
    area += std::abs((t[1] - t[0]).cross(t[2] - t[0])) / 2;
  }
  EXPECT_NEAR(area, 140.0 * 140.0, 1.0) << "the triangles tile the object's grid";
}

TEST(LabelSpread, FeaturesWithoutDepthAreLeftAsTheyAre) {
  Layout l = wallAndObject();
  l.depth[0] = std::numeric_limits<double>::quiet_NaN();  // a wall corner
  l.labels[0] = -1;
  const LabelSpreadResult r = spreadMotionLabels(buildSurfaceGraph(l.uv, l.depth, kImage), l.labels);
  EXPECT_EQ(r.labels[0], -1);
}

TEST(LabelSpread, MismatchedSizesAreRefused) {
  const Layout l = wallAndObject();
  std::vector<int8_t> short_labels(l.labels.begin(), l.labels.end() - 1);
  EXPECT_THROW(spreadMotionLabels(buildSurfaceGraph(l.uv, l.depth, kImage), short_labels), DataError);
  const std::vector<double> short_depth(l.depth.begin(), l.depth.end() - 1);
  EXPECT_THROW(buildSurfaceGraph(l.uv, short_depth, kImage), DataError);
}

// The flood: one flagged feature in the object's corner, the rest of the object unjudged but
// for a few judged still (a dragged check), the wall still. A majority vote would stop at the
// still ones; the flood covers every unjudged object feature and never crosses onto the wall.
TEST(LabelFlood, OneFlaggedFeatureTakesTheUnjudgedRestOfItsSurfaceAndNotTheWall) {
  Layout l = wallAndObject();
  int seed = -1, object_unjudged = 0;
  for (size_t i = 0; i < l.labels.size(); ++i) {
    if (!l.object[i]) continue;
    if (seed < 0) {
      seed = static_cast<int>(i);
      l.labels[i] = 1;
    } else {
      l.labels[i] = i % 5 == 0 ? 0 : -1;  // every fifth judged still
      object_unjudged += l.labels[i] < 0;
    }
  }
  std::vector<int8_t> labels = l.labels;
  const int flooded = floodMovingLabels(buildSurfaceGraph(l.uv, l.depth, kImage), {seed}, &labels);
  EXPECT_EQ(flooded, object_unjudged);
  for (size_t i = 0; i < labels.size(); ++i) {
    if (!l.object[i]) EXPECT_EQ(labels[i], l.labels[i]) << "wall feature " << i;
    else if (l.labels[i] == 0) EXPECT_EQ(labels[i], 0) << "judged features keep their label";
    else EXPECT_EQ(labels[i], 1) << "object feature " << i;
  }
  std::vector<int8_t> too_few(3, -1);
  EXPECT_THROW(floodMovingLabels(buildSurfaceGraph(l.uv, l.depth, kImage), {}, &too_few), DataError);
}

}  // namespace
}  // namespace plslam
