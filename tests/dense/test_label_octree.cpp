// The labelled octree (octomap_labels.ot): its node rules, its round trip through OctoMap's
// factory, class ids of a synthetic scene's voxels read back from the written file, and the
// README's palette legend against the code.
#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <cctype>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/log.h"
#include "dense/dense_products.h"
#include "dense/label_octree.h"
#include "dense_scene.h"
#include "dynamic/class_list.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

// Sets the eight leaves under the voxel of (x, y, z) at depth 15 to occupied, with the
// classes `classes[i]` (one vote each).
void setEightLeaves(LabelOcTree* tree, const octomap::point3d& corner, const std::vector<int16_t>& classes) {
  const double r = tree->getResolution();
  for (int i = 0; i < 8; ++i) {
    const octomap::point3d p(corner.x() + (0.5 + (i & 1)) * r, corner.y() + (0.5 + ((i >> 1) & 1)) * r,
                             corner.z() + (0.5 + ((i >> 2) & 1)) * r);
    LabelOcTreeNode* n = tree->updateNode(p, true, /*lazy_eval=*/true);
    const Rgb c = classColour(classes[i]);
    n->setLabel(classes[i], 1, 1, c.r, c.g, c.b);
  }
}

}  // namespace

TEST(LabelOctree, InnerNodesTakeTheMajorityAndPruningKeepsMixedLabels) {
  LabelOcTree tree(0.1);
  // Block A: eight persons (prunable). Block B: five chairs (56), three persons: not prunable.
  setEightLeaves(&tree, octomap::point3d(0, 0, 0), std::vector<int16_t>(8, 0));
  setEightLeaves(&tree, octomap::point3d(1.6, 0, 0), {56, 0, 56, 0, 56, 0, 56, 56});
  tree.updateInnerOccupancy();
  tree.prune();
  const LabelOcTreeNode* a = tree.search(0.05, 0.05, 0.05);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->classId(), 0);
  EXPECT_EQ(a->points(), 8u) << "a pruned block sums its children's points";
  EXPECT_EQ(a->votes(), 8u);
  size_t leaves_b = 0;
  for (auto it = tree.begin_leafs(), e = tree.end_leafs(); it != e; ++it)
    if (it.getX() > 1.0) {
      ++leaves_b;
      EXPECT_DOUBLE_EQ(it.getSize(), 0.1) << "mixed labels must not be pruned";
    }
  EXPECT_EQ(leaves_b, 8u);
  // The parent of block B (depth 15): chairs win 5 to 3.
  const LabelOcTreeNode* b = tree.search(1.65, 0.05, 0.05, tree.getTreeDepth() - 1);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->classId(), 56);
  EXPECT_EQ(b->votes(), 5u);
  EXPECT_EQ(b->points(), 8u);
}

TEST(LabelOctree, RoundTripsThroughOctomapsFactory) {
  LabelOcTree tree(0.05);
  setEightLeaves(&tree, octomap::point3d(0.4, -0.2, 1.0), {3, -1, 3, 3, 7, -1, 3, 3});
  tree.updateNode(octomap::point3d(2, 2, 2), false);  // a free voxel: no label
  tree.updateInnerOccupancy();
  std::stringstream file;
  ASSERT_TRUE(tree.write(file));
  std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(file));
  ASSERT_NE(any, nullptr) << "the type must be registered with OctoMap's factory";
  EXPECT_EQ(any->getTreeType(), LabelOcTree::kTreeType);
  auto* back = dynamic_cast<LabelOcTree*>(any.get());
  ASSERT_NE(back, nullptr);
  EXPECT_DOUBLE_EQ(back->getResolution(), 0.05);
  ASSERT_EQ(back->size(), tree.size());
  for (auto it = tree.begin_leafs(), e = tree.end_leafs(); it != e; ++it) {
    const LabelOcTreeNode* n = back->search(it.getKey());
    ASSERT_NE(n, nullptr);
    EXPECT_TRUE(*n == *it) << "voxel at " << it.getCoordinate();
  }
}

TEST(LabelOctree, WrittenFileGivesTheSceneVoxelsTheirClasses) {
  // The dynamic scene with its persons kept in (no rejection): person voxels and static ones.
  const test::GtMapOptions o = test::personsKeptMapOptions();
  const test::GtMap g = test::buildGtMap(o);
  const DenseProducts p = buildDenseProducts(g.map, g.scene.camera(), o.dense);
  ASSERT_FALSE(p.cancelled);
  const std::string dir = test::scratchDir("label_octree");
  writeDenseProducts(dir, p, {}, o.dense);

  std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(dir + "/" + kOctomapLabelsOt));
  auto* tree = dynamic_cast<LabelOcTree*>(any.get());
  ASSERT_NE(tree, nullptr) << "octomap_labels.ot must read back as a LabelOcTree";
  std::unique_ptr<octomap::AbstractOcTree> colour_any(octomap::AbstractOcTree::read(dir + "/" + kOctomapSemanticOt));
  auto* colour = dynamic_cast<octomap::ColorOcTree*>(colour_any.get());
  ASSERT_NE(colour, nullptr);

  // Truth per occupied voxel, in the scene: a person's voxel lies on a person's part at a
  // keyframe time and away from static surfaces; a static voxel lies on a static surface,
  // away from every person's path.
  const SE3 T_scene_map = g.T_scene_world * p.frame.T_map_world.inverse();
  std::vector<synth::Box> persons;
  for (TimeNs t : g.keyframe_times)
    for (const synth::Box& b : g.scene.movingBoxes(t)) persons.push_back(b);
  const auto personDistance = [&](const Eigen::Vector3d& q) {
    double d = 1e9;
    for (const synth::Box& b : persons) d = std::min(d, b.signedDistance(q));
    return d;
  };
  const double half_diagonal = 0.87 * tree->getResolution();
  size_t person_voxels = 0, person_right = 0, static_voxels = 0, static_right = 0, labelled = 0;
  for (auto it = tree->begin_leafs(), e = tree->end_leafs(); it != e; ++it) {
    if (!tree->isNodeOccupied(*it) || it->points() == 0) continue;
    ++labelled;
    EXPECT_LE(it->votes(), it->points());
    // The colour tree has the same colour at the same voxel.
    const octomap::ColorOcTreeNode* c = colour->search(it.getKey());
    ASSERT_NE(c, nullptr);
    EXPECT_TRUE(c->getColor() == octomap::ColorOcTreeNode::Color(it->r(), it->g(), it->b()));
    if (it->classId() >= 0) {
      const Rgb palette = classColour(it->classId());
      EXPECT_TRUE(palette.r == it->r() && palette.g == it->g() && palette.b == it->b());
    }
    const octomap::point3d m = it.getCoordinate();
    const Eigen::Vector3d q = T_scene_map * Eigen::Vector3d(m.x(), m.y(), m.z());
    const double to_static = g.scene.staticSurfaceDistance(q), to_person = personDistance(q);
    if (to_person <= half_diagonal && to_static > 0.2) person_voxels++, person_right += it->classId() == 0;
    if (to_static <= half_diagonal && to_person > 0.3) static_voxels++, static_right += it->classId() == -1;
  }
  std::printf("labels: %zu labelled occupied voxels; person %zu/%zu, static %zu/%zu with the true class\n", labelled,
              person_right, person_voxels, static_right, static_voxels);
  ASSERT_GT(person_voxels, 10u) << "the persons must be in the map for this test to mean anything";
  ASSERT_GT(static_voxels, 100u);
  EXPECT_GE(person_right, 0.9 * person_voxels);
  EXPECT_GE(static_right, 0.99 * static_voxels);
}

// The README's legend (between the markers) is the palette of the built-in COCO list; on a
// mismatch the expected block is printed, ready to paste.
TEST(PaletteLegend, ReadmeTableMatchesThePalette) {
  const ClassList coco = ClassList::coco();
  std::string expected;
  for (size_t k = 0; k < coco.size(); ++k) {
    const Rgb c = classColour(static_cast<int>(k));
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c.r, c.g, c.b);
    expected += str("| ", k, " | ", coco.name(static_cast<int>(k)), " | `", hex, "` | ", int(c.r), ", ", int(c.g), ", ",
                    int(c.b), " |\n");
  }
  const std::string readme = test::readFile(test::sourceDir() + "/README.md");
  const std::string begin = "<!-- palette legend: begin -->", end = "<!-- palette legend: end -->";
  const size_t b = readme.find(begin), e = readme.find(end);
  ASSERT_NE(b, std::string::npos) << "README.md has no " << begin;
  ASSERT_NE(e, std::string::npos) << "README.md has no " << end;
  std::istringstream block(readme.substr(b, e - b));
  std::string line, rows;
  while (std::getline(block, line))
    if (line.size() > 2 && line[0] == '|' && std::isdigit(static_cast<unsigned char>(line[2]))) rows += line + "\n";
  EXPECT_EQ(rows, expected) << "the README legend differs from the palette; expected rows:\n" << expected;
}
