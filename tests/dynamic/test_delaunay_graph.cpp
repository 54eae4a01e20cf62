#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>

#include "core/error.h"
#include "dynamic/delaunay_graph.h"

using namespace plslam;

namespace {
std::set<std::pair<int, int>> edgeSet(const DelaunayGraph& g) {
  std::set<std::pair<int, int>> s;
  for (const auto& e : g.edges) s.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  return s;
}
}  // namespace

TEST(DelaunayGraph, AFanAroundACentreGivesItsEdgesAndTrianglesByTheCallersIndices) {
  // A square's corners (indices 10-13) and its centre (14), pushed off-centre so that no four
  // points lie on one circle: the triangulation is the fan around the centre.
  const std::vector<cv::Point2f> pixels = {{100, 100}, {300, 100}, {300, 300}, {100, 300}, {190, 210}};
  const std::vector<int> index = {10, 11, 12, 13, 14};
  const DelaunayGraph g = triangulateFeatures(pixels, index, cv::Size(640, 480));
  EXPECT_EQ(g.vertices, index);
  const std::set<std::pair<int, int>> expected = {{10, 11}, {11, 12}, {12, 13}, {10, 13},
                                                  {10, 14}, {11, 14}, {12, 14}, {13, 14}};
  EXPECT_EQ(edgeSet(g), expected);
  EXPECT_EQ(g.edges.size(), expected.size());  // each once
  ASSERT_EQ(g.triangles.size(), 4u);
  ASSERT_EQ(g.triangle_pixels.size(), 4u);
  for (size_t k = 0; k < g.triangles.size(); ++k) {
    EXPECT_NE(std::find(g.triangles[k].begin(), g.triangles[k].end(), 14), g.triangles[k].end());
    for (int c = 0; c < 3; ++c) {
      const auto at = std::find(index.begin(), index.end(), g.triangles[k][c]) - index.begin();
      EXPECT_EQ(g.triangle_pixels[k][c], pixels[static_cast<size_t>(at)]);
    }
  }
}

TEST(DelaunayGraph, ARepeatedPixelIsTheFirstOnesVertexAndTooFewPixelsGiveNoEdges) {
  const std::vector<cv::Point2f> pixels = {{10, 10}, {50, 10}, {10, 10}, {30, 40}};
  const DelaunayGraph g = triangulateFeatures(pixels, {0, 1, 2, 3}, cv::Size(64, 64));
  EXPECT_EQ(g.vertices, (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(edgeSet(g), (std::set<std::pair<int, int>>{{0, 1}, {1, 3}, {0, 3}}));
  EXPECT_EQ(g.triangles.size(), 1u);

  const DelaunayGraph two = triangulateFeatures({{10, 10}, {50, 10}, {10, 10}}, {0, 1, 2}, cv::Size(64, 64));
  EXPECT_EQ(two.vertices, (std::vector<int>{0, 1}));
  EXPECT_TRUE(two.edges.empty());
  EXPECT_TRUE(two.triangles.empty());
  EXPECT_THROW(triangulateFeatures({{1, 1}}, {}, cv::Size(64, 64)), DataError);
}
