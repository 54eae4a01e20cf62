#include "dense/label_octree.h"

#include <istream>
#include <ostream>
#include <utility>
#include <vector>

namespace plslam {

namespace {

template <typename T>
void writeRaw(std::ostream& s, const T& v) {
  s.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
void readRaw(std::istream& s, T* v) {
  s.read(reinterpret_cast<char*>(v), sizeof(T));
}

}  // namespace

bool LabelOcTreeNode::operator==(const LabelOcTreeNode& rhs) const {
  return rhs.value == value && sameLabel(rhs) && rhs.votes_ == votes_ && rhs.points_ == points_;
}

bool LabelOcTreeNode::sameLabel(const LabelOcTreeNode& o) const {
  return o.class_id_ == class_id_ && o.r_ == r_ && o.g_ == g_ && o.b_ == b_;
}

void LabelOcTreeNode::copyData(const LabelOcTreeNode& from) {
  OcTreeNode::copyData(from);
  class_id_ = from.class_id_;
  votes_ = from.votes_;
  points_ = from.points_;
  r_ = from.r_, g_ = from.g_, b_ = from.b_;
}

void LabelOcTreeNode::setLabel(int16_t class_id, uint32_t votes, uint32_t points, uint8_t r, uint8_t g, uint8_t b) {
  class_id_ = class_id;
  votes_ = votes;
  points_ = points;
  r_ = r, g_ = g, b_ = b;
}

void LabelOcTreeNode::updateLabelChildren() {
  if (!children) return;
  // Votes per class over the children, with the colour of the first child of each class.
  std::vector<std::pair<const LabelOcTreeNode*, uint32_t>> classes;
  uint32_t points = 0;
  for (int i = 0; i < 8; ++i) {
    if (!children[i]) continue;
    const auto* c = static_cast<const LabelOcTreeNode*>(children[i]);
    if (c->points_ == 0) continue;  // no fused point below: no say
    points += c->points_;
    bool found = false;
    for (auto& [first, votes] : classes)
      if (first->class_id_ == c->class_id_) votes += c->votes_, found = true;
    if (!found) classes.push_back({c, c->votes_});
  }
  if (classes.empty()) return;
  const LabelOcTreeNode* best = classes.front().first;
  uint32_t best_votes = classes.front().second;
  for (const auto& [first, votes] : classes)
    if (votes > best_votes || (votes == best_votes && first->class_id_ > best->class_id_))
      best = first, best_votes = votes;
  setLabel(best->class_id_, best_votes, points, best->r_, best->g_, best->b_);
}

std::istream& LabelOcTreeNode::readData(std::istream& s) {
  readRaw(s, &value);
  readRaw(s, &class_id_);
  readRaw(s, &votes_);
  readRaw(s, &points_);
  readRaw(s, &r_);
  readRaw(s, &g_);
  readRaw(s, &b_);
  return s;
}

std::ostream& LabelOcTreeNode::writeData(std::ostream& s) const {
  writeRaw(s, value);
  writeRaw(s, class_id_);
  writeRaw(s, votes_);
  writeRaw(s, points_);
  writeRaw(s, r_);
  writeRaw(s, g_);
  writeRaw(s, b_);
  return s;
}

LabelOcTree::Registration LabelOcTree::registration_;

LabelOcTree::Registration::Registration() {
  auto* prototype = new LabelOcTree(0.1);
  prototype->clearKeyRays();
  octomap::AbstractOcTree::registerTreeType(prototype);  // OctoMap's mapping owns it
}

LabelOcTree::LabelOcTree(double resolution) : OccupancyOcTreeBase<LabelOcTreeNode>(resolution) {
  registration_.ensureLinking();
}

bool LabelOcTree::isNodeCollapsible(const LabelOcTreeNode* node) const {
  if (!nodeChildExists(node, 0)) return false;
  const LabelOcTreeNode* first = getNodeChild(node, 0);
  if (nodeHasChildren(first)) return false;
  for (unsigned i = 1; i < 8; ++i) {
    if (!nodeChildExists(node, i)) return false;
    const LabelOcTreeNode* c = getNodeChild(node, i);
    if (nodeHasChildren(c) || c->getValue() != first->getValue() || !c->sameLabel(*first)) return false;
  }
  return true;
}

bool LabelOcTree::pruneNode(LabelOcTreeNode* node) {
  if (!isNodeCollapsible(node)) return false;
  uint32_t votes = 0, points = 0;
  for (unsigned i = 0; i < 8; ++i) {
    votes += getNodeChild(node, i)->votes();
    points += getNodeChild(node, i)->points();
  }
  OccupancyOcTreeBase<LabelOcTreeNode>::pruneNode(node);  // copies child 0, deletes the children
  node->votes_ = votes;
  node->points_ = points;
  return true;
}

void LabelOcTree::updateInnerOccupancy() {
  if (root) updateInnerRecurs(root, 0);
}

void LabelOcTree::updateInnerRecurs(LabelOcTreeNode* node, unsigned depth) {
  if (!nodeHasChildren(node)) return;
  if (depth < tree_depth)
    for (unsigned i = 0; i < 8; ++i)
      if (nodeChildExists(node, i)) updateInnerRecurs(getNodeChild(node, i), depth + 1);
  node->updateOccupancyChildren();
  node->updateLabelChildren();
}

}  // namespace plslam
