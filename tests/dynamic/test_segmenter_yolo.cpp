// The YOLOv8-seg backend with the real model (shared/models), on TUM fr3 sitting_static
// frames (two people at a desk) and on a synthetic static frame. Skipped visibly without
// ../shared. Speed is not asserted.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/error.h"
#include "dynamic/yolo_segmenter.h"
#include "support/test_support.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam {
namespace {

const char* kModel = "models/yolov8n-seg-320.onnx";
const char* kFr3 = "data/tum/fr3_sitting_static_150";

std::string modelPath() { return test::sharedDir() + "/" + kModel; }

// The model is loaded once for the tests of this file.
class YoloSegmenterTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (test::sharedDir().empty() || !test::pathExists(modelPath())) return;
    YoloSegOptions o;
    o.model_path = modelPath();
    const std::string names = test::sharedDir() + "/models/coco.names";
    segmenter_ = std::make_unique<YoloSegmenter>(o, test::pathExists(names) ? ClassList::load(names) : ClassList::coco());
  }
  static void TearDownTestSuite() { segmenter_.reset(); }
  static std::unique_ptr<YoloSegmenter> segmenter_;
};
std::unique_ptr<YoloSegmenter> YoloSegmenterTest::segmenter_;

// Colour images of the fr3 folder listed in rgb.txt, by index.
std::vector<std::string> fr3Images() {
  const std::string dir = test::sharedDir() + "/" + kFr3;
  std::ifstream in(dir + "/rgb.txt");
  std::vector<std::string> paths;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string stamp, file;
    if (ls >> stamp >> file) paths.push_back(dir + "/" + file);
  }
  return paths;
}

// Every labelled pixel of instance k lies in instances[k-1].box; ids are 1..K.
void expectLabelsConsistent(const Segmentation& s) {
  ASSERT_EQ(s.instance_ids.type(), CV_16UC1);
  double max_id = 0;
  cv::minMaxLoc(s.instance_ids, nullptr, &max_id);
  EXPECT_LE(max_id, static_cast<double>(s.instances.size()));
  for (size_t k = 0; k < s.instances.size(); ++k) {
    const Instance& inst = s.instances[k];
    EXPECT_EQ(inst.id, static_cast<int>(k) + 1);
    EXPECT_GE(inst.score, YoloSegOptions().confidence);
    EXPECT_FALSE(inst.box.empty());
    if (k > 0) {
      EXPECT_LE(inst.score, s.instances[k - 1].score) << "ordered by score, so overlaps go to the better one";
    }
    const cv::Mat own = s.instance_ids == inst.id;
    const int total = cv::countNonZero(own);
    const int in_box = inst.box.empty() ? 0 : cv::countNonZero(own(inst.box));
    EXPECT_EQ(in_box, total) << "instance " << inst.id << " (" << inst.class_name << ") has pixels outside its box";
  }
}

TEST_F(YoloSegmenterTest, ReadsInputSizeAndLayoutFromTheModel) {
  PLSLAM_REQUIRE_SHARED(kModel);
  ASSERT_TRUE(segmenter_);
  EXPECT_EQ(segmenter_->inputSize(), cv::Size(320, 320));
  const YoloSegLayout& l = segmenter_->layout();
  EXPECT_EQ(l.num_classes, 80);
  EXPECT_EQ(l.num_masks, 32);
  EXPECT_EQ(l.num_anchors, 2100);
  EXPECT_EQ(l.proto_height, 80);
  EXPECT_EQ(l.proto_width, 80);
  EXPECT_EQ(segmenter_->name(), "yolo");
}

TEST_F(YoloSegmenterTest, FindsThePeopleOfFr3SittingStatic) {
  PLSLAM_REQUIRE_SHARED(kModel);
  PLSLAM_REQUIRE_SHARED(kFr3);
  ASSERT_TRUE(segmenter_);
  const std::vector<std::string> images = fr3Images();
  ASSERT_GE(images.size(), 150u);
  for (size_t i : {0u, 70u, 140u}) {
    const cv::Mat bgr = cv::imread(images[i], cv::IMREAD_COLOR);
    ASSERT_FALSE(bgr.empty()) << images[i];
    const Segmentation s = segmenter_->segment(bgr, static_cast<TimeNs>(i));
    EXPECT_EQ(s.t_ns, static_cast<TimeNs>(i));
    ASSERT_EQ(s.instance_ids.size(), bgr.size());
    EXPECT_GT(s.ms, 0.0);
    expectLabelsConsistent(s);
    int people = 0;
    for (const Instance& inst : s.instances) {
      if (inst.class_name != "person" || inst.score <= 0.5f) continue;
      EXPECT_EQ(inst.class_id, 0);
      EXPECT_TRUE(inst.potentially_dynamic);
      const double area = cv::countNonZero(s.instance_ids == inst.id) / static_cast<double>(bgr.total());
      EXPECT_GT(area, 0.03) << images[i] << " person " << inst.id << " box " << inst.box;
      EXPECT_LT(area, 0.60) << images[i] << " person " << inst.id << " box " << inst.box;
      ++people;
    }
    EXPECT_GE(people, 1) << images[i];
  }
}

TEST_F(YoloSegmenterTest, SameImageGivesTheSameSegmentation) {
  PLSLAM_REQUIRE_SHARED(kModel);
  PLSLAM_REQUIRE_SHARED(kFr3);
  ASSERT_TRUE(segmenter_);
  const cv::Mat bgr = cv::imread(fr3Images().at(10), cv::IMREAD_COLOR);
  const Segmentation a = segmenter_->segment(bgr, 1), b = segmenter_->segment(bgr, 1);
  ASSERT_EQ(a.instances.size(), b.instances.size());
  EXPECT_EQ(cv::countNonZero(a.instance_ids != b.instance_ids), 0);
  for (size_t k = 0; k < a.instances.size(); ++k) EXPECT_EQ(a.instances[k].box, b.instances[k].box);
}

TEST_F(YoloSegmenterTest, NoPersonInASyntheticStaticFrame) {
  PLSLAM_REQUIRE_SHARED(kModel);
  ASSERT_TRUE(segmenter_);
  synth::SceneOptions so;
  so.frames = 30;
  so.aa_samples = 2;
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kStatic, so);
  for (int i : {0, 29}) {
    const Segmentation s = segmenter_->segment(synth::render(scene, i).bgr, scene.frameTime(i));
    expectLabelsConsistent(s);
    for (const Instance& inst : s.instances)
      EXPECT_NE(inst.class_name, "person") << "frame " << i << " score " << inst.score << " box " << inst.box;
  }
}

TEST_F(YoloSegmenterTest, RefusesWrongImagesAndMismatchedClassLists) {
  PLSLAM_REQUIRE_SHARED(kModel);
  ASSERT_TRUE(segmenter_);
  EXPECT_THROW(segmenter_->segment(cv::Mat(), 0), DataError);
  EXPECT_THROW(segmenter_->segment(cv::Mat(48, 64, CV_8UC1, cv::Scalar(0)), 0), DataError);
  YoloSegOptions o;
  o.model_path = modelPath();
  try {
    YoloSegmenter bad(o, ClassList::fromNames({"person", "car", "dog"}, "three.names"));
    ADD_FAILURE() << "a 3-name list was accepted for an 80-class model";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("three.names"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("80"), std::string::npos) << e.what();
  }
  o.input_size = 640;
  EXPECT_THROW(YoloSegmenter(o, ClassList::coco()), ConfigError) << "the model fixes 320x320";
}

}  // namespace
}  // namespace plslam
