// The product files read back with the tools users have: PCL for the PCD, a plain PLY
// parse, OctoMap for .bt / .ot. (The only test file that includes PCL.)
#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

#include "dense/dense_products.h"
#include "dense_scene.h"
#include "support/test_support.h"

using namespace plslam;

TEST(DenseFiles, EveryProductIsWrittenAndReadsBack) {
  // Persons kept in (no rejection) so the files carry a class.
  const test::GtMapOptions o = test::personsKeptMapOptions();
  const test::GtMap g = test::buildGtMap(o);
  std::vector<std::string> stages;
  const auto record = [&](const std::string& stage, size_t, size_t) {
    if (stages.empty() || stages.back() != stage) stages.push_back(stage);
    return true;
  };
  const DenseProducts p = buildDenseProducts(g.map, g.scene.camera(), o.dense, {}, record);
  EXPECT_EQ(stages, (std::vector<std::string>{"cloud", "octomap", "semantic octomap", "grid"}));
  ASSERT_FALSE(p.cancelled);
  size_t persons = 0;
  for (const FusedPoint& q : p.cloud) persons += q.class_id == 0;
  ASSERT_GT(persons, 0u) << "the persons must be in the cloud for this test to mean anything";

  const std::string dir = test::scratchDir("dense_files");
  const std::vector<WrittenFile> files = writeDenseProducts(dir, p, {}, o.dense);
  std::map<std::string, uintmax_t> sizes;
  for (const WrittenFile& f : files) {
    sizes[std::filesystem::path(f.path).filename().string()] = f.bytes;
    EXPECT_EQ(std::filesystem::file_size(f.path), f.bytes) << f.path;
  }
  for (const char* name : {kMapFrameYaml, kDenseCloudPcd, kDenseCloudPly, kOctomapBt, kOctomapSemanticOt, kOctomapLabelsOt, kGridPgm, kGridYaml,
                           kDenseSummaryJson})
    EXPECT_EQ(sizes.count(name), 1u) << name;
  // No temporary file is left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();

  // PCD: PCL reads it; positions, colours and labels (class + 1) as written.
  pcl::PointCloud<pcl::PointXYZRGBL> pcd;
  ASSERT_EQ(pcl::io::loadPCDFile(dir + "/" + kDenseCloudPcd, pcd), 0);
  ASSERT_EQ(pcd.size(), p.cloud.size());
  size_t labelled = 0;
  for (size_t i = 0; i < pcd.size(); ++i) {
    EXPECT_EQ(pcd[i].x, p.cloud[i].p_w.x());
    EXPECT_EQ(pcd[i].z, p.cloud[i].p_w.z());
    EXPECT_EQ(pcd[i].r, p.cloud[i].r);
    EXPECT_EQ(pcd[i].b, p.cloud[i].b);
    EXPECT_EQ(static_cast<int>(pcd[i].label), p.cloud[i].class_id + 1);
    labelled += pcd[i].label == 1;
  }
  EXPECT_EQ(labelled, persons);

  // PLY: header as documented, one 19-byte record per point, person points in the palette red.
  const std::string ply = test::readFile(dir + "/" + kDenseCloudPly);
  const size_t end = ply.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = ply.substr(0, end);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex " + std::to_string(p.cloud.size()) + "\n"), std::string::npos);
  EXPECT_NE(header.find("property int class"), std::string::npos);
  const char* data = ply.data() + end + std::strlen("end_header\n");
  ASSERT_EQ(ply.size() - (data - ply.data()), p.cloud.size() * 19);
  const Rgb red = classColour(0);
  EXPECT_GT(red.r, 200);
  EXPECT_LT(red.g, 100);
  size_t red_persons = 0;
  for (size_t i = 0; i < p.cloud.size(); ++i) {
    int32_t cls;
    std::memcpy(&cls, data + i * 19 + 15, 4);
    ASSERT_EQ(cls, p.cloud[i].class_id);
    const auto* c = reinterpret_cast<const uint8_t*>(data + i * 19 + 12);
    if (cls == 0) red_persons += c[0] == red.r && c[1] == red.g && c[2] == red.b;
    else EXPECT_TRUE(c[0] == c[1] && c[1] == c[2]) << "unlabelled points are grey";
  }
  EXPECT_EQ(red_persons, persons);

  // OctoMaps: the binary tree reads back with the same leaves; the colour tree has red voxels.
  octomap::OcTree bt(0.1);
  ASSERT_TRUE(bt.readBinary(dir + "/" + kOctomapBt));
  EXPECT_EQ(bt.getNumLeafNodes(), p.octree->getNumLeafNodes());
  EXPECT_DOUBLE_EQ(bt.getResolution(), o.dense.octree_resolution_m);
  std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(dir + "/" + kOctomapSemanticOt));
  auto* colour = dynamic_cast<octomap::ColorOcTree*>(any.get());
  ASSERT_NE(colour, nullptr);
  size_t red_voxels = 0, occupied = 0;
  for (auto it = colour->begin_leafs(), e = colour->end_leafs(); it != e; ++it) {
    if (!colour->isNodeOccupied(*it)) continue;
    ++occupied;
    const octomap::ColorOcTreeNode::Color c = it->getColor();
    red_voxels += c.r == red.r && c.g == red.g && c.b == red.b;
  }
  std::printf("files: %zu points (%zu person), %zu occupied colour voxels (%zu person red)\n", p.cloud.size(), persons,
              occupied, red_voxels);
  EXPECT_GT(red_voxels, 0u);
  EXPECT_LT(red_voxels, occupied);

  const nlohmann::json json = test::readJson(dir + "/" + kDenseSummaryJson);
  EXPECT_EQ(json.at("fused_points"), p.cloud.size());
  ASSERT_FALSE(json.at("costs").empty());
  EXPECT_TRUE(json.at("costs")[0].at("peak_rss_mb").is_number());
}

TEST(DenseFiles, StoppedBuildWritesNoProduct) {
  test::GtMapOptions o;
  o.frames = 30;
  o.every = 10;
  const test::GtMap g = test::buildGtMap(o);
  const DenseProducts p =
      buildDenseProducts(g.map, g.scene.camera(), o.dense, {},
                         [](const std::string& stage, size_t, size_t) { return stage != "octomap"; });
  EXPECT_TRUE(p.cancelled);
  const std::string dir = test::scratchDir("dense_cancelled");
  const std::vector<WrittenFile> files = writeDenseProducts(dir, p, {}, o.dense);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(std::filesystem::path(files[0].path).filename(), kDenseSummaryJson);
  EXPECT_NE(test::readFile(files[0].path).find("\"cancelled\": true"), std::string::npos);
}
