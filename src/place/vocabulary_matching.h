// Descriptor matching through the vocabulary (ORB-SLAM's SearchByBoW): each descriptor is
// compared only with the other side's descriptors under the same vocabulary node a few
// levels below the root, instead of with all of them. With k = 10 and the node two levels
// down there are 100 groups, so matching two frames of 1000 keypoints costs about 1 % of
// brute force; the price is the few true pairs that the tree splits into neighbouring nodes.
// The tracker uses it against its reference keyframe when the motion model fails and to
// relocalise against the keyframes a place query returns.
//
// Stateless. Thread safety: every function may be called concurrently.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "core/frame.h"
#include "features/matching.h"
#include "place/keyframe_database.h"
#include "place/vocabulary.h"

namespace plslam {

/// Depth below the root of the nodes that group descriptors for matching.
constexpr int kMatchingNodeDepth = 2;

/// What the vocabulary makes of one frame: bags of words (for place queries) and, per
/// descriptor row, its node at kMatchingNodeDepth (for matching).
struct FrameWords {
  KeyframeBow bow;
  std::vector<int> point_nodes;  ///< per keypoint
  std::vector<int> line_nodes;   ///< per segment
};
FrameWords describeWords(const VocabularySet& vocabulary, const FrameFeatures& features);

/// The nodes of descriptor rows (CV_8U, 32 columns) at kMatchingNodeDepth; `bow` (optional)
/// gets their bag of words.
std::vector<int> matchingNodes(const Vocabulary& vocabulary, const cv::Mat& descriptors, BowVector* bow = nullptr);

/// Query rows matched with train rows under the same node: the closest within
/// `options.max_distance`, better than `options.ratio` times the second closest in the node;
/// each train row goes to its closest query (`options.mutual` is implied). Rows whose node
/// is negative (the `usable` test of the caller, e.g. no landmark) are skipped. Sorted by
/// query index.
std::vector<DescriptorMatch> matchByVocabulary(const cv::Mat& query, const std::vector<int>& query_nodes,
                                               const cv::Mat& train, const std::vector<int>& train_nodes,
                                               const BruteForceOptions& options);

}  // namespace plslam
