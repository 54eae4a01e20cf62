// The Delaunay triangulation of feature pixels, by feature index: what the label spreading
// and the Delaunay motion check both build every frame. OpenCV's Subdiv2D triangulates and
// lists edges and triangles by their corners' coordinates; those are mapped back to the
// caller's indices through one hash table of the inserted pixels.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace plslam {

struct DelaunayGraph {
  /// The indices that became vertices, in input order (of equal pixels, the first).
  std::vector<int> vertices;
  /// Each edge once, in Subdiv2D's edge order; both ends are indices given to triangulateFeatures.
  std::vector<std::array<int, 2>> edges;
  /// In Subdiv2D's triangle order, corners in its order.
  std::vector<std::array<int, 3>> triangles;
  /// The corners' pixels of triangles[k], as Subdiv2D gives them.
  std::vector<std::array<cv::Point2f, 3>> triangle_pixels;
};

/// One key per undirected edge between the vertices with indices a and b (a set of edges).
inline int64_t undirectedEdgeKey(int a, int b) {
  return (static_cast<int64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}

/// Triangulates `pixels[k]` under the index `index[k]`; the pixels must lie inside `image`. A
/// pixel equal to an earlier one is left out (the earlier one stands for both). Edges and
/// triangles touching Subdiv2D's virtual outer vertices are left out. Fewer than three
/// distinct pixels: vertices only. Throws DataError when the two lists differ in length.
DelaunayGraph triangulateFeatures(const std::vector<cv::Point2f>& pixels, const std::vector<int>& index,
                                  cv::Size image);

}  // namespace plslam
