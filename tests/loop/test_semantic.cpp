// Semantic instance matching: agreeing layouts raise the score, a single generic class
// does not, a different layout lowers it, dynamic instances are ignored.
#include <gtest/gtest.h>

#include "loop/semantic_match.h"

using namespace plslam;

namespace {
KeyframeInstance inst(int cls, const std::string& name, cv::Rect box, Eigen::Vector3d c, bool dynamic = false) {
  KeyframeInstance i;
  i.class_id = cls;
  i.class_name = name;
  i.box = box;
  i.centroid_c = c;
  i.dynamic = dynamic;
  return i;
}
constexpr double kDiagonal = 800;

std::vector<KeyframeInstance> office() {
  return {inst(56, "chair", {100, 200, 80, 120}, {-0.8, 0.3, 2.0}), inst(62, "tv", {300, 100, 120, 80}, {0.1, -0.3, 2.5}),
          inst(58, "potted plant", {500, 220, 60, 100}, {1.0, 0.2, 2.2}),
          inst(73, "refrigerator", {520, 40, 100, 300}, {1.4, -0.2, 3.0})};
}
}  // namespace

TEST(SemanticMatch, SameLayoutRaisesTheScore) {
  std::vector<KeyframeInstance> b = office();
  for (auto& i : b) i.box.x += 20, i.centroid_c.x() += 0.05;  // a slightly different viewpoint
  const SemanticResult r = matchInstances(office(), b, kDiagonal, {});
  EXPECT_EQ(r.matches.size(), 4u);
  EXPECT_GT(r.factor, 1.0);
  EXPECT_FALSE(r.refuted);
}

TEST(SemanticMatch, OneSharedGenericClassAloneDoesNotMakeTwoPlacesAlike) {
  const std::vector<KeyframeInstance> a = {inst(56, "chair", {100, 200, 80, 120}, {-0.8, 0.3, 2.0})};
  const std::vector<KeyframeInstance> b = {inst(56, "chair", {110, 210, 80, 120}, {-0.7, 0.3, 2.1})};
  const SemanticResult r = matchInstances(a, b, kDiagonal, {});
  EXPECT_EQ(r.matches.size(), 1u);
  EXPECT_DOUBLE_EQ(r.factor, 1.0) << "one chair is no evidence either way";
}

TEST(SemanticMatch, SameClassesInADifferentLayoutLowerTheScore) {
  // The same four classes, placed elsewhere in the image and in depth.
  std::vector<KeyframeInstance> b = office();
  b[0].box = {520, 300, 80, 120}, b[0].centroid_c = {1.2, 0.5, 4.0};
  b[1].box = {20, 300, 120, 80}, b[1].centroid_c = {-1.5, 0.5, 1.0};
  b[2].box = {100, 20, 60, 100}, b[2].centroid_c = {-1.0, -0.8, 3.8};
  b[3].box = {250, 250, 100, 200}, b[3].centroid_c = {0.0, 0.3, 1.2};
  const SemanticResult r = matchInstances(office(), b, kDiagonal, {});
  EXPECT_TRUE(r.matches.empty());
  EXPECT_TRUE(r.refuted);
  EXPECT_LT(r.factor, 1.0);
}

TEST(SemanticMatch, PositionsAreCheckedUnderTheGivenPoseAndDynamicInstancesIgnored) {
  const std::vector<KeyframeInstance> a = office();
  std::vector<KeyframeInstance> b = office();
  b.push_back(inst(0, "person", {300, 200, 100, 250}, {0.0, 0.0, 1.5}, true));
  const SE3 far(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.0, 0, 0));
  const SemanticResult wrong = matchInstances(a, b, kDiagonal, {}, far);
  EXPECT_TRUE(wrong.matches.empty()) << "1 m apart under the pose";
  EXPECT_TRUE(wrong.refuted);
  const SemanticResult right = matchInstances(a, b, kDiagonal, {}, SE3());
  EXPECT_EQ(right.matches.size(), 4u);
  EXPECT_EQ(right.static_b, 4) << "the dynamic person does not count";
  EXPECT_GT(right.factor, 1.0);
}
