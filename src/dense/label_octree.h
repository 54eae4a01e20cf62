// An OctoMap occupancy octree whose voxels carry a semantic class id: the tree of
// `octomap_labels.ot` (dense/octree_maps.h builds it, dense/dense_products.h writes it).
//
// Each node holds OctoMap's occupancy (log-odds) plus
//   class_id  the class of the voxel (index into the segmenter's class list; -1: no class),
//   votes     the fused points of that class in the voxel,
//   points    all fused points in the voxel (votes / points: how sure the label is),
//   r, g, b   the semantic colour (the class's palette colour, grey luminance for no class),
// written after the log-odds in that order (int16, uint32, uint32, 3 x uint8, host byte
// order as OctoMap writes its floats).
//
// Fusion rule (one rule for leaves and inner nodes): the label is the majority of the points,
// "no class" counting as a candidate; a tie goes to the larger class id. An inner node takes
// the class with the most votes over its children (votes and points summed), so a coarse
// query answers for the majority of what lies below. Pruning merges eight children only when
// they agree on occupancy, class and colour, so no label is lost to pruning.
//
// Registration: the tree type "PlslamLabelOcTree" is registered with OctoMap's factory when
// plslam_dense is loaded (a static member, as ColorOcTree does), so
// octomap::AbstractOcTree::read("octomap_labels.ot") returns a LabelOcTree in any program
// that links plslam_dense. Programs that do not (octovis, octomap_server) cannot create the
// type: octovis shows "Cannot open OcTree file"; for them octomap_semantic.ot (ColorOcTree,
// same colours) is written beside it.
#pragma once

#include <octomap/OccupancyOcTreeBase.h>
#include <octomap/OcTreeNode.h>

#include <cstdint>
#include <iosfwd>
#include <string>

namespace plslam {

class LabelOcTree;

class LabelOcTreeNode : public octomap::OcTreeNode {
 public:
  friend class LabelOcTree;
  LabelOcTreeNode() = default;
  LabelOcTreeNode(const LabelOcTreeNode& rhs) = default;
  bool operator==(const LabelOcTreeNode& rhs) const;

  /// Called by the tree (pruning, expansion): occupancy and label, not the children.
  void copyData(const LabelOcTreeNode& from);
  /// Sets the label of a leaf (class_id -1: no class).
  void setLabel(int16_t class_id, uint32_t votes, uint32_t points, uint8_t r, uint8_t g, uint8_t b);
  int16_t classId() const { return class_id_; }
  uint32_t votes() const { return votes_; }
  uint32_t points() const { return points_; }
  uint8_t r() const { return r_; }
  uint8_t g() const { return g_; }
  uint8_t b() const { return b_; }
  /// Same class and colour (what pruning needs to merge).
  bool sameLabel(const LabelOcTreeNode& other) const;
  /// Inner nodes: the majority class of the children (see above).
  void updateLabelChildren();

  /// File I/O of one node (log-odds, then the label).
  std::istream& readData(std::istream& s);
  std::ostream& writeData(std::ostream& s) const;

 private:
  int16_t class_id_ = -1;
  uint32_t votes_ = 0, points_ = 0;
  uint8_t r_ = 128, g_ = 128, b_ = 128;
};

class LabelOcTree : public octomap::OccupancyOcTreeBase<LabelOcTreeNode> {
 public:
  explicit LabelOcTree(double resolution);
  /// OctoMap's virtual constructor (the factory clones the registered prototype).
  LabelOcTree* create() const override { return new LabelOcTree(resolution); }
  std::string getTreeType() const override { return kTreeType; }
  static constexpr const char* kTreeType = "PlslamLabelOcTree";

  /// Merges eight children only when they agree on occupancy and label.
  bool isNodeCollapsible(const LabelOcTreeNode* node) const override;
  bool pruneNode(LabelOcTreeNode* node) override;
  /// Inner occupancy (max of the children, as OcTree) and inner labels (see above).
  void updateInnerOccupancy();

 private:
  void updateInnerRecurs(LabelOcTreeNode* node, unsigned depth);

  // Puts the prototype into OctoMap's class-id mapping once, when the library loads.
  struct Registration {
    Registration();
    void ensureLinking() {}
  };
  static Registration registration_;
};

}  // namespace plslam
