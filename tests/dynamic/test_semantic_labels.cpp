// The semantic labels a keyframe keeps: the class image and the instance descriptions.
#include <gtest/gtest.h>

#include <cmath>

#include "dynamic/semantic_labels.h"
#include "synth/renderer.h"

namespace plslam {
namespace {

// Two instances on a fronto-parallel plane at 2 m: a person (class 0) on the left that the
// fusion judged dynamic, a chair (class 56) on the right that it kept.
struct TwoInstances {
  PinholeCamera cam = synth::syntheticCamera(640, 480);
  Segmentation seg;
  std::vector<InstanceDecision> decisions;
  cv::Mat depth;
  TwoInstances() {
    seg.instance_ids = cv::Mat::zeros(480, 640, CV_16UC1);
    seg.instance_ids(cv::Rect(100, 100, 80, 200)).setTo(1);
    seg.instance_ids(cv::Rect(400, 200, 120, 60)).setTo(2);
    Instance person, chair;
    person.id = 1, person.class_id = 0, person.class_name = "person", person.box = cv::Rect(100, 100, 80, 200);
    chair.id = 2, chair.class_id = 56, chair.class_name = "chair", chair.box = cv::Rect(400, 200, 120, 60);
    seg.instances = {person, chair};
    decisions.resize(2);
    decisions[0].dynamic = true;
    decisions[1].dynamic = false;
    depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(2.0f));
  }
};

TEST(SemanticLabels, ClassImageHasEachInstancesClassAndMinusOneElsewhere) {
  const TwoInstances s;
  const cv::Mat c = classImage(s.seg);
  ASSERT_EQ(c.type(), CV_16SC1);
  EXPECT_EQ(c.at<int16_t>(150, 120), 0);
  EXPECT_EQ(c.at<int16_t>(230, 450), 56);
  EXPECT_EQ(c.at<int16_t>(10, 10), -1);
  EXPECT_EQ(cv::countNonZero(c == 56), 120 * 60);
  EXPECT_TRUE(classImage(Segmentation{}).empty());
}

TEST(SemanticLabels, InstancesCarryClassAreaDecisionAndTheirCentroidInTheCameraFrame) {
  const TwoInstances s;
  const std::vector<KeyframeInstance> out = describeInstances(s.seg, s.decisions, s.depth, s.cam);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].class_name, "person");
  EXPECT_TRUE(out[0].dynamic);
  EXPECT_FALSE(out[1].dynamic);
  EXPECT_EQ(out[0].pixels, 80 * 200);
  EXPECT_EQ(out[1].box, cv::Rect(400, 200, 120, 60));
  // The chair's centre pixel (460, 230) at 2 m.
  const Eigen::Vector3d expected = s.cam.unproject(Eigen::Vector2d(460, 230), 2.0);
  EXPECT_NEAR((out[1].centroid_c - expected).norm(), 0.0, 0.01);
  EXPECT_NEAR(out[0].centroid_c.z(), 2.0, 1e-6);
}

TEST(SemanticLabels, AnInstanceWithoutDepthHasNoCentroid) {
  TwoInstances s;
  s.depth(cv::Rect(400, 200, 120, 60)).setTo(std::numeric_limits<float>::quiet_NaN());
  const std::vector<KeyframeInstance> out = describeInstances(s.seg, {}, s.depth, s.cam);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[1].centroid_c.array().isNaN().all());
  EXPECT_TRUE(std::isfinite(out[0].centroid_c.z()));
  EXPECT_FALSE(out[0].dynamic);  // no decisions: none dynamic
}

}  // namespace
}  // namespace plslam
