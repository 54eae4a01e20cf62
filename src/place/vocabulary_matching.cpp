#include "place/vocabulary_matching.h"

#include <algorithm>
#include <unordered_map>

#include "core/error.h"

namespace plslam {

std::vector<int> matchingNodes(const Vocabulary& vocabulary, const cv::Mat& descriptors, BowVector* bow) {
  std::vector<int> nodes(descriptors.rows, -1);
  if (descriptors.empty() || vocabulary.empty()) {
    if (bow) bow->clear();
    return nodes;
  }
  if (descriptors.type() != CV_8U || descriptors.cols != 32)
    throw DataError("matchingNodes: descriptors must be 32-byte CV_8U rows");
  for (int r = 0; r < descriptors.rows; ++r) vocabulary.word(descriptors.ptr<uint8_t>(r), kMatchingNodeDepth, &nodes[r]);
  if (bow) *bow = vocabulary.transform(descriptors);
  return nodes;
}

FrameWords describeWords(const VocabularySet& vocabulary, const FrameFeatures& f) {
  FrameWords w;
  w.point_nodes = matchingNodes(vocabulary.orb, f.point_descriptors, &w.bow.orb);
  w.line_nodes = matchingNodes(vocabulary.lbd, f.line_descriptors, &w.bow.lbd);
  return w;
}

std::vector<DescriptorMatch> matchByVocabulary(const cv::Mat& query, const std::vector<int>& query_nodes,
                                               const cv::Mat& train, const std::vector<int>& train_nodes,
                                               const BruteForceOptions& o) {
  std::unordered_map<int, std::vector<int>> train_by_node;
  for (int t = 0; t < static_cast<int>(train_nodes.size()) && t < train.rows; ++t)
    if (train_nodes[t] >= 0) train_by_node[train_nodes[t]].push_back(t);
  std::vector<DescriptorMatch> best_of_train(train.rows);  // the closest query of each train row
  for (int q = 0; q < static_cast<int>(query_nodes.size()) && q < query.rows; ++q) {
    const auto group = query_nodes[q] < 0 ? train_by_node.end() : train_by_node.find(query_nodes[q]);
    if (group == train_by_node.end()) continue;
    int best = -1, best_d = 257, second_d = 257;
    for (int t : group->second) {
      const int d = hammingDistance(query.ptr<uint8_t>(q), train.ptr<uint8_t>(t));
      if (d < best_d) second_d = best_d, best_d = d, best = t;
      else if (d < second_d) second_d = d;
    }
    if (best < 0 || best_d > o.max_distance) continue;
    if (o.ratio < 1.f && second_d <= 256 && best_d >= o.ratio * second_d) continue;
    DescriptorMatch& held = best_of_train[best];
    if (held.query < 0 || best_d < held.distance) held = {q, best, best_d};
  }
  std::vector<DescriptorMatch> out;
  for (const DescriptorMatch& m : best_of_train)
    if (m.query >= 0) out.push_back(m);
  std::sort(out.begin(), out.end(), [](const DescriptorMatch& a, const DescriptorMatch& b) { return a.query < b.query; });
  return out;
}

}  // namespace plslam
