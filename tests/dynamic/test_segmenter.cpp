// Segmenter interface without the real model: class lists, the ONNX checks, the none and
// replay backends, the factory and the letterbox geometry.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/error.h"
#include "dynamic/class_list.h"
#include "dynamic/onnx_check.h"
#include "dynamic/segmenter.h"
#include "dynamic/yolo_segmenter.h"
#include "support/test_support.h"
#include "synth/renderer.h"
#include "synth/scene.h"

namespace plslam {
namespace {

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

std::string readFile(const std::string& path, size_t max_bytes = std::string::npos) {
  std::ifstream in(path, std::ios::binary);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return s.substr(0, max_bytes);
}

// Expects `fn` to throw E with all of `parts` in its message.
template <typename E, typename F>
void expectThrowWith(F fn, const std::vector<std::string>& parts) {
  try {
    fn();
    ADD_FAILURE() << "no exception";
  } catch (const E& e) {
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << " lacks " << p;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

// ------------------------------------------------------------------- class list

TEST(ClassList, LoadsNamesWithCrlfBomSpacesAndTrailingBlankLines) {
  const std::string dir = test::scratchDir("classes_crlf");
  writeFile(dir + "/n.names", "\xEF\xBB\xBFperson\r\n  bicycle \r\ntraffic light\r\n\r\n\n");
  const ClassList c = ClassList::load(dir + "/n.names");
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.name(0), "person");
  EXPECT_EQ(c.name(1), "bicycle");
  EXPECT_EQ(c.name(2), "traffic light");
  EXPECT_EQ(c.find("traffic light"), 2);
  EXPECT_EQ(c.find("Person"), 0);
  EXPECT_EQ(c.find("giraffe"), -1);
  EXPECT_EQ(c.name(7), "class7");
  // The default dynamic set keeps the names the file has.
  EXPECT_TRUE(c.isDynamic(0));
  EXPECT_TRUE(c.isDynamic(1));
  EXPECT_FALSE(c.isDynamic(2));
  EXPECT_FALSE(c.isDynamic(-1));
  EXPECT_FALSE(c.isDynamic(3));
}

TEST(ClassList, RefusesMissingEmptyInnerBlankAndRepeatedNamesNamingTheFile) {
  const std::string dir = test::scratchDir("classes_bad");
  expectThrowWith<IoError>([&] { ClassList::load(dir + "/missing.names"); }, {dir + "/missing.names"});
  writeFile(dir + "/empty.names", "");
  expectThrowWith<IoError>([&] { ClassList::load(dir + "/empty.names"); }, {dir + "/empty.names", "empty"});
  writeFile(dir + "/blanks.names", "\n\r\n  \n");
  expectThrowWith<IoError>([&] { ClassList::load(dir + "/blanks.names"); }, {dir + "/blanks.names", "empty"});
  writeFile(dir + "/hole.names", "person\n\ncar\n");
  expectThrowWith<IoError>([&] { ClassList::load(dir + "/hole.names"); }, {dir + "/hole.names", "line 2"});
  writeFile(dir + "/twice.names", "person\ncar\nperson\n");
  expectThrowWith<IoError>([&] { ClassList::load(dir + "/twice.names"); }, {dir + "/twice.names", "person"});
  expectThrowWith<ConfigError>([&] { ClassList::fromNames({}, "mine"); }, {"mine"});
}

TEST(ClassList, DefaultDynamicSetIsPeopleVehiclesAndAnimalsOfCoco) {
  const ClassList c = ClassList::coco();
  ASSERT_EQ(c.size(), 80u);
  EXPECT_EQ(c.name(0), "person");
  EXPECT_EQ(c.dynamicNames(), ClassList::defaultDynamicNames()) << "all default names exist, in COCO order";
  for (const char* n : {"person", "bicycle", "car", "motorbike", "bus", "train", "truck", "boat", "bird", "cat", "dog",
                        "horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe"})
    EXPECT_TRUE(c.isDynamic(c.find(n))) << n;
  for (const char* n : {"chair", "tvmonitor", "laptop", "traffic light", "teddy bear", "aeroplane"})
    EXPECT_FALSE(c.isDynamic(c.find(n))) << n;
  // The other COCO spellings find the same classes.
  EXPECT_EQ(c.find("motorcycle"), c.find("motorbike"));
  EXPECT_EQ(c.find("airplane"), 4);
  EXPECT_EQ(c.find("couch"), c.find("sofa"));
  EXPECT_EQ(c.find("tv"), c.find("tvmonitor"));
  EXPECT_EQ(c.find("dining table"), c.find("diningtable"));
}

TEST(ClassList, SharedCocoNamesFileMatchesTheBuiltinList) {
  PLSLAM_REQUIRE_SHARED("models/coco.names");
  const ClassList f = ClassList::load(test::sharedDir() + "/models/coco.names");
  EXPECT_EQ(f.names(), ClassList::coco().names());
  EXPECT_EQ(f.dynamicNames(), ClassList::defaultDynamicNames());
}

TEST(ClassList, ConfigurableDynamicSetRefusesUnknownNames) {
  ClassList c = ClassList::coco();
  c.setDynamic({"person", "Motorcycle", "chair"});
  EXPECT_EQ(c.dynamicNames(), (std::vector<std::string>{"person", "motorbike", "chair"}));
  expectThrowWith<ConfigError>([&] { c.setDynamic({"person", "unicorn"}); }, {"unicorn", "<builtin coco>"});
  EXPECT_EQ(c.dynamicNames().size(), 3u) << "a refused set leaves the previous one";
  c.setDynamic({});
  EXPECT_TRUE(c.dynamicNames().empty());
}

// ------------------------------------------------------------------- ONNX checks

// Protobuf encoding, enough to write small ONNX models by hand.
std::string varint(uint64_t v) {
  std::string s;
  do {
    uint8_t b = v & 0x7f;
    v >>= 7;
    s.push_back(static_cast<char>(b | (v ? 0x80 : 0)));
  } while (v);
  return s;
}
std::string fieldVarint(int f, uint64_t v) { return varint(static_cast<uint64_t>(f) << 3) + varint(v); }
std::string fieldBytes(int f, const std::string& b) { return varint((static_cast<uint64_t>(f) << 3) | 2) + varint(b.size()) + b; }
std::string valueInfo(const std::string& name, const std::vector<int64_t>& dims, bool typed = true) {
  if (!typed) return fieldBytes(1, name);
  std::string shape;
  for (int64_t d : dims) shape += fieldBytes(1, d >= 0 ? fieldVarint(1, d) : fieldBytes(2, "batch"));
  // Float tensor; an empty dims gives a shape without dimensions (OpenCV wants the field).
  const std::string tensor = fieldVarint(1, 1) + fieldBytes(2, shape);
  return fieldBytes(1, name) + fieldBytes(2, fieldBytes(1, tensor));
}
std::string node(const std::string& op, const std::string& in, const std::string& out) {
  return fieldBytes(1, in) + fieldBytes(2, out) + fieldBytes(3, out + "_node") + fieldBytes(4, op);
}
// A model whose graph applies `op` to the image input once per output.
std::string handModel(const std::string& op, const std::vector<std::string>& outputs, bool typed_outputs,
                      const std::vector<int64_t>& out_dims) {
  std::string graph;
  for (const auto& o : outputs) graph += fieldBytes(1, node(op, "images", o));
  graph += fieldBytes(2, "hand");
  graph += fieldBytes(11, valueInfo("images", {1, 3, 64, 64}));
  for (const auto& o : outputs) graph += fieldBytes(12, valueInfo(o, out_dims, typed_outputs));
  return fieldVarint(1, 7) + fieldBytes(2, "plslam-test") + fieldBytes(7, graph) + fieldBytes(8, fieldVarint(2, 13));
}

TEST(OnnxCheck, ReadsTheFramingOfAHandWrittenModel) {
  const std::string bytes = handModel("Identity", {"a", "b"}, true, {-1, 116, 2100});
  const OnnxModelInfo info = inspectOnnxBytes(bytes, "hand");
  EXPECT_EQ(info.ir_version, 7);
  EXPECT_EQ(info.producer, "plslam-test");
  ASSERT_EQ(info.inputs.size(), 1u);
  EXPECT_EQ(info.inputs[0].name, "images");
  EXPECT_EQ(info.inputs[0].dims, (std::vector<int64_t>{1, 3, 64, 64}));
  ASSERT_EQ(info.outputs.size(), 2u);
  EXPECT_EQ(info.outputs[1].name, "b");
  EXPECT_EQ(info.outputs[1].dims, (std::vector<int64_t>{-1, 116, 2100}));
  // Every prefix of it is refused cleanly (truncation anywhere), never a crash.
  for (size_t n = 0; n < bytes.size(); ++n) EXPECT_THROW(inspectOnnxBytes(bytes.substr(0, n), "hand"), IoError) << n;
}

TEST(OnnxCheck, RefusesEmptyRandomTextAndGraphlessFilesNamingThem) {
  const std::string dir = test::scratchDir("onnx_bad");
  expectThrowWith<IoError>([&] { inspectOnnxFile(dir + "/missing.onnx"); }, {dir + "/missing.onnx", "missing"});
  writeFile(dir + "/empty.onnx", "");
  expectThrowWith<IoError>([&] { inspectOnnxFile(dir + "/empty.onnx"); }, {dir + "/empty.onnx", "empty"});
  writeFile(dir + "/text.onnx", "this is not a model\nbut a text file\n");
  expectThrowWith<IoError>([&] { inspectOnnxFile(dir + "/text.onnx"); }, {dir + "/text.onnx", "not an ONNX model"});
  writeFile(dir + "/nograph.onnx", fieldVarint(1, 7) + fieldBytes(2, "x"));
  expectThrowWith<IoError>([&] { inspectOnnxFile(dir + "/nograph.onnx"); }, {dir + "/nograph.onnx", "no graph"});
  // Random bytes, also ones that start like an ONNX file: refused, never a crash.
  std::mt19937 rng(7);
  int refused = 0;
  const int trials = 3000;
  for (int trial = 0; trial < trials; ++trial) {
    std::string bytes(1 + rng() % 2000, '\0');
    for (char& ch : bytes) ch = static_cast<char>(rng() & 0xff);
    if (trial % 2) bytes[0] = 0x08;
    if (trial % 4 == 3) bytes[1] = 7;  // a plausible ir_version too
    try {
      if (trial < 3) {
        const std::string path = dir + "/random" + std::to_string(trial) + ".onnx";
        writeFile(path, bytes);
        expectThrowWith<IoError>([&] { inspectOnnxFile(path); }, {path, "not an ONNX model"});
      }
      inspectOnnxBytes(bytes, "random");
    } catch (const IoError&) {
      ++refused;
    }
  }
  EXPECT_EQ(refused, trials);
}

TEST(OnnxCheck, YoloSegOutputLayout) {
  const YoloSegLayout l = checkYoloSegOutputs({{1, 32, 80, 80}, {1, 116, 2100}}, "m");
  EXPECT_EQ(l.detections_output, 1);
  EXPECT_EQ(l.num_classes, 80);
  EXPECT_EQ(l.num_masks, 32);
  EXPECT_EQ(l.num_anchors, 2100);
  EXPECT_EQ(l.proto_height, 80);
  EXPECT_EQ(l.proto_width, 80);
  const YoloSegLayout two = checkYoloSegOutputs({{1, 4 + 2 + 8, 50}, {1, 8, 20, 30}}, "m");
  EXPECT_EQ(two.num_classes, 2);
  EXPECT_EQ(two.proto_width, 30);
  expectThrowWith<DataError>([] { checkYoloSegOutputs({{1, 84, 2100}}, "det.onnx"); }, {"det.onnx", "1 output"});
  expectThrowWith<DataError>([] { checkYoloSegOutputs({{1, 116, 2100}, {1, 116, 2100}}, "m.onnx"); }, {"m.onnx", "3-D"});
  expectThrowWith<DataError>([] { checkYoloSegOutputs({{1, 36, 2100}, {1, 32, 80, 80}}, "m.onnx"); },
                             {"m.onnx", "no class scores"});
  expectThrowWith<DataError>([] { checkYoloSegOutputs({{2, 116, 2100}, {2, 32, 80, 80}}, "m.onnx"); }, {"batch"});
}

TEST(OnnxCheck, SegmenterRefusesModelsOpenCvCannotLoadOrOfTheWrongShape) {
  const std::string dir = test::scratchDir("onnx_models");
  YoloSegOptions o;
  // Declared outputs of the wrong shape: refused before OpenCV reads the file.
  o.model_path = dir + "/declared.onnx";
  writeFile(o.model_path, handModel("Identity", {"out"}, true, {1, 3, 64, 64}));
  expectThrowWith<DataError>([&] { YoloSegmenter(o, ClassList::coco()); }, {o.model_path, "1 output"});
  // An operator OpenCV does not know.
  o.model_path = dir + "/unknown_op.onnx";
  writeFile(o.model_path, handModel("NoSuchOperator", {"a", "b"}, true, {}));
  expectThrowWith<IoError>([&] { YoloSegmenter(o, ClassList::coco()); }, {o.model_path, "OpenCV cannot load"});
  // A model OpenCV runs, whose real outputs are not YOLOv8-seg's (no declared shapes).
  o.model_path = dir + "/identity.onnx";
  writeFile(o.model_path, handModel("Identity", {"a", "b"}, true, {}));
  expectThrowWith<DataError>([&] { YoloSegmenter(o, ClassList::coco()); }, {o.model_path, "[1, 3, 64, 64]"});
}

TEST(OnnxCheck, TruncatedRealModelIsRefusedNamingTheFile) {
  PLSLAM_REQUIRE_SHARED("models/yolov8n-seg-320.onnx");
  const std::string real = test::sharedDir() + "/models/yolov8n-seg-320.onnx";
  const OnnxModelInfo info = inspectOnnxFile(real);
  ASSERT_EQ(info.inputs.size(), 1u);
  EXPECT_EQ(info.inputs[0].name, "images");
  EXPECT_EQ(info.inputs[0].dims, (std::vector<int64_t>{1, 3, 320, 320}));
  ASSERT_EQ(info.outputs.size(), 2u);
  EXPECT_EQ(info.outputs[0].name, "output0");
  EXPECT_EQ(info.outputs[0].dims, (std::vector<int64_t>{1, 116, 2100}));
  EXPECT_EQ(info.outputs[1].dims, (std::vector<int64_t>{1, 32, 80, 80}));

  const std::string dir = test::scratchDir("onnx_truncated");
  const std::string cut = dir + "/cut.onnx";
  writeFile(cut, readFile(real, 1024));
  expectThrowWith<IoError>([&] { inspectOnnxFile(cut); }, {cut, "truncated"});
  YoloSegOptions o;
  o.model_path = cut;
  expectThrowWith<IoError>([&] { YoloSegmenter(o, ClassList::coco()); }, {cut, "truncated"});
}

// ------------------------------------------------------------------- none, replay, factory

TEST(NoneSegmenter, GivesAZeroLabelImageOfTheFrameSize) {
  NoneSegmenter none;
  const cv::Mat bgr(37, 53, CV_8UC3, cv::Scalar(1, 2, 3));
  const Segmentation s = none.segment(bgr, 42);
  EXPECT_EQ(s.t_ns, 42);
  EXPECT_TRUE(s.instances.empty());
  ASSERT_EQ(s.instance_ids.type(), CV_16UC1);
  EXPECT_EQ(s.instance_ids.size(), bgr.size());
  EXPECT_EQ(cv::countNonZero(s.instance_ids), 0);
  EXPECT_GE(s.ms, 0.0);
  EXPECT_EQ(none.name(), "none");
  EXPECT_THROW(none.segment(cv::Mat(), 0), DataError);
  EXPECT_THROW(none.segment(cv::Mat(4, 4, CV_8UC1), 0), DataError);
}

TEST(ReplaySegmenter, BoxesClassesAndCompactIdsFromAMaskWithOverlappingBoxes) {
  cv::Mat mask(80, 100, CV_16UC1, cv::Scalar(0));
  mask(cv::Rect(10, 5, 30, 40)).setTo(700);  // person
  // An L-shaped chair whose box overlaps the person's.
  mask(cv::Rect(35, 30, 40, 10)).setTo(3);
  mask(cv::Rect(65, 30, 10, 45)).setTo(3);
  mask(cv::Rect(90, 70, 5, 5)).setTo(900);  // no label
  ReplaySegmenter replay({{700, 0, "person"}, {3, 56, "chair"}, {12, 2, "car"}});
  const Segmentation s = replay.fromMask(mask, 5);
  ASSERT_EQ(s.instances.size(), 3u) << "only ids present in the mask";
  const Instance& chair = s.instances[0];
  const Instance& person = s.instances[1];
  const Instance& unknown = s.instances[2];
  EXPECT_EQ(chair.id, 1);
  EXPECT_EQ(chair.source_id, 3);
  EXPECT_EQ(chair.class_id, 56);
  EXPECT_EQ(chair.class_name, "chair");
  EXPECT_FALSE(chair.potentially_dynamic);
  EXPECT_EQ(chair.box, cv::Rect(35, 30, 40, 45));
  EXPECT_EQ(person.id, 2);
  EXPECT_EQ(person.source_id, 700);
  EXPECT_EQ(person.class_name, "person");
  EXPECT_TRUE(person.potentially_dynamic);
  EXPECT_EQ(person.box, cv::Rect(10, 5, 30, 40));
  EXPECT_FLOAT_EQ(person.score, 1.0f);
  EXPECT_EQ(unknown.class_id, -1);
  EXPECT_EQ(unknown.class_name, "unknown");
  EXPECT_TRUE(unknown.potentially_dynamic);
  EXPECT_EQ(unknown.box, cv::Rect(90, 70, 5, 5));
  ASSERT_EQ(s.instance_ids.size(), mask.size());
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      const int src = mask.at<uint16_t>(y, x);
      const int expected = src == 0 ? 0 : src == 3 ? 1 : src == 700 ? 2 : 3;
      ASSERT_EQ(s.instance_ids.at<uint16_t>(y, x), expected) << x << "," << y;
    }
  // The dynamic set decides by class name.
  ClassList classes = ClassList::coco();
  classes.setDynamic({"chair"});
  const Segmentation s2 = ReplaySegmenter({{700, 0, "person"}, {3, 56, "chair"}}, classes).fromMask(mask, 5);
  EXPECT_TRUE(s2.instances[0].potentially_dynamic);
  EXPECT_FALSE(s2.instances[1].potentially_dynamic);
}

TEST(ReplaySegmenter, ReadsFrameMasksOrTheMaskSourceAndCountsMissingMasks) {
  cv::Mat mask(20, 30, CV_16UC1, cv::Scalar(0));
  mask(cv::Rect(2, 3, 4, 5)).setTo(1);
  RgbdFrame frame;
  frame.t_ns = 77;
  frame.bgr = cv::Mat(20, 30, CV_8UC3, cv::Scalar(0));
  frame.instance_ids = mask;
  ReplaySegmenter replay({{1, 0, "person"}}, ClassList::coco(),
                         [&](TimeNs t) { return t == 77 ? mask : cv::Mat(); });
  Segmentation a = replay.segment(frame);
  ASSERT_EQ(a.instances.size(), 1u);
  EXPECT_EQ(a.instances[0].box, cv::Rect(2, 3, 4, 5));
  EXPECT_EQ(a.t_ns, 77);
  Segmentation b = replay.segment(frame.bgr, 77);
  ASSERT_EQ(b.instances.size(), 1u);
  EXPECT_EQ(replay.framesWithoutMask(), 0);
  Segmentation c = replay.segment(frame.bgr, 78);  // the source has nothing at 78
  EXPECT_TRUE(c.instances.empty());
  EXPECT_EQ(c.instance_ids.size(), frame.bgr.size());
  EXPECT_EQ(cv::countNonZero(c.instance_ids), 0);
  frame.instance_ids = cv::Mat();
  EXPECT_TRUE(replay.segment(frame).instances.empty());
  EXPECT_EQ(replay.framesWithoutMask(), 2);
  // A mask of another size or type is refused.
  frame.instance_ids = cv::Mat(10, 30, CV_16UC1, cv::Scalar(0));
  EXPECT_THROW(replay.segment(frame), DataError);
  frame.instance_ids = cv::Mat(20, 30, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(replay.segment(frame), DataError);
  EXPECT_THROW(ReplaySegmenter({{1, 0, "person"}, {1, 2, "car"}}), ConfigError);
}

TEST(ReplaySegmenter, ReplaysTheSyntheticDynamicSceneMasks) {
  synth::SceneOptions so;
  so.frames = 60;
  so.width = 320;
  so.height = 240;
  so.aa_samples = 1;
  const synth::Scene scene = synth::makeScene(synth::SceneKind::kDynamic, so);
  std::vector<InstanceClass> labels;
  for (const auto& m : scene.movingObjects()) labels.push_back({m.instance_id, m.class_id, m.class_name});
  ReplaySegmenter replay(labels);
  int seen = 0;
  for (int i : {0, 30, 59}) {
    const synth::RenderedFrame f = synth::render(scene, i);
    const Segmentation s = replay.segment(f.toRgbdFrame());
    for (const Instance& inst : s.instances) {
      ++seen;
      EXPECT_EQ(inst.class_name, "person");
      EXPECT_TRUE(inst.potentially_dynamic);
      cv::Mat own = f.instance_ids == inst.source_id;
      EXPECT_EQ(cv::boundingRect(own), inst.box);
      EXPECT_EQ(cv::countNonZero(s.instance_ids == inst.id), cv::countNonZero(own));
    }
  }
  EXPECT_GT(seen, 0) << "the dynamic scene shows its persons";
}

TEST(SegmenterFactory, BuildsBackendsAndFallsBackOnlyWhenAllowed) {
  EXPECT_EQ(parseSegmenterKind("yolo"), SegmenterKind::kYolo);
  EXPECT_THROW(parseSegmenterKind("mask-rcnn"), ConfigError);
  SegmenterOptions o;
  EXPECT_EQ(makeSegmenter(o)->name(), "none");
  o.kind = SegmenterKind::kReplay;
  o.replay_labels = {{1, 0, "person"}};
  EXPECT_EQ(makeSegmenter(o)->name(), "replay");
  o.dynamic_classes = std::vector<std::string>{"person", "dragon"};
  expectThrowWith<ConfigError>([&] { makeSegmenter(o); }, {"dragon"});
  o.dynamic_classes.reset();

  const std::string dir = test::scratchDir("factory");
  o.kind = SegmenterKind::kYolo;
  o.yolo.model_path = dir + "/absent.onnx";
  expectThrowWith<IoError>([&] { makeSegmenter(o); }, {o.yolo.model_path});
  o.allow_missing_model = true;
  std::string reason;
  auto fallback = makeSegmenter(o, &reason);
  EXPECT_EQ(fallback->name(), "none");
  EXPECT_NE(reason.find(o.yolo.model_path), std::string::npos) << reason;
  // Configuration mistakes are not excused by allow_missing_model.
  o.yolo.threads = 2;
  expectThrowWith<ConfigError>([&] { makeSegmenter(o); }, {"threads"});
  o.yolo.threads = 0;
  o.classes_file = dir + "/absent.names";
  expectThrowWith<IoError>([&] { makeSegmenter(o); }, {o.classes_file});
}

// ------------------------------------------------------------------- letterbox geometry

TEST(Letterbox, NonSquareImageMapsPointsAndMasksBackToTheSamePlace) {
  for (const cv::Size input : {cv::Size(320, 320), cv::Size(320, 256)}) {
    const cv::Size image(640, 360);
    const Letterbox lb = makeLetterbox(image, input);
    EXPECT_NEAR(lb.scale_x, lb.scale_y, 0.01);
    EXPECT_LE(lb.resized.width, input.width);
    EXPECT_LE(lb.resized.height, input.height);
    EXPECT_TRUE(lb.resized.width == input.width || lb.resized.height == input.height) << "the largest fit";
    EXPECT_NEAR(lb.pad_x, (input.width - lb.resized.width) / 2.0, 0.5) << "centred";
    EXPECT_NEAR(lb.pad_y, (input.height - lb.resized.height) / 2.0, 0.5);
    for (const cv::Point2d p : {cv::Point2d(0, 0), cv::Point2d(640, 360), cv::Point2d(123.25, 77.5)}) {
      const cv::Point2d q = lb.inputToImage(lb.imageToInput(p));
      EXPECT_NEAR(q.x, p.x, 1e-9);
      EXPECT_NEAR(q.y, p.y, 1e-9);
    }
    // The image corners land on the resized area's corners inside the padding.
    EXPECT_NEAR(lb.imageToInput({0, 0}).x, lb.pad_x, 1e-9);
    EXPECT_NEAR(lb.imageToInput({640, 360}).y, lb.pad_y + lb.resized.height, 1e-9);

    // A mask drawn at a known place, letterboxed like the image, seen at the input
    // resolution and at the coarser prototype resolution, maps back to the same place.
    const cv::Rect truth(400, 100, 120, 200);
    cv::Mat mask(image, CV_32FC1, cv::Scalar(0));
    mask(truth).setTo(1);
    cv::Mat in_map = applyLetterbox(mask, lb);
    ASSERT_EQ(in_map.size(), input);
    ASSERT_GT(lb.pad_y, 0);
    EXPECT_EQ(in_map.at<float>(0, 0), 114.0f) << "padded with 114";
    in_map.setTo(0, in_map > 1.5f);  // the padding is no mask
    cv::Mat proto;
    cv::resize(in_map, proto, cv::Size(input.width / 4, input.height / 4), 0, 0, cv::INTER_AREA);
    for (const cv::Mat* map : {&in_map, &proto}) {
      const double image_px_per_map_px = static_cast<double>(input.width) / map->cols / lb.scale_x;
      const cv::Mat back = unletterboxMap(*map, lb, cv::Rect(cv::Point(0, 0), image)) > 0.5;
      const cv::Rect found = cv::boundingRect(back);
      const double tol = 0.75 * image_px_per_map_px + 1;
      EXPECT_NEAR(found.x, truth.x, tol) << map->size();
      EXPECT_NEAR(found.y, truth.y, tol);
      EXPECT_NEAR(found.br().x, truth.br().x, tol);
      EXPECT_NEAR(found.br().y, truth.br().y, tol);
      // A sub-window gives the same values as the whole image there.
      const cv::Rect roi(390, 90, 50, 40);
      const cv::Mat part = unletterboxMap(*map, lb, roi);
      const cv::Mat whole = unletterboxMap(*map, lb, cv::Rect(cv::Point(0, 0), image))(roi);
      EXPECT_LT(cv::norm(part, whole, cv::NORM_INF), 1e-3);
    }
    // Boxes: an input-space box around the drawn rectangle maps back onto it.
    const cv::Point2d a = lb.imageToInput(truth.tl()), b = lb.imageToInput(truth.br());
    EXPECT_EQ(lb.boxToImage(cv::Rect2d(a, b)), truth);
    EXPECT_EQ(lb.boxToImage(cv::Rect2d(-50, -50, 1000, 1000)), cv::Rect(cv::Point(0, 0), image)) << "clipped";
  }
}

}  // namespace
}  // namespace plslam
