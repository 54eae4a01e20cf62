// The bad-input corpus: one case per failure a user can meet with `plslam run`, each run
// through the built executable as a user would. Every case must end in either
//   - a refusal: exit code 1 or 2, a message naming the input and the problem, and the
//     output folder left as it was (good outputs of an earlier run survive), or
//   - a counted, logged skip where the run can go on: exit 0, the skip named in the
//     messages, counted in stats.json;
// never a crash (death by a signal, sanitizer report) and never a silent wrong result.
// The cases are generated at run time from the synthetic sequence into scratch folders.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <vector>

#include "support/test_support.h"
#include "system/synthetic_cache.h"

using namespace plslam;
namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 12;
// What a run writes into --out.
const char* const kOutputs[] = {"trajectory.txt", "keyframes.txt", "sparse_map.ply", "stats.json", "config.yaml",
                                 "map.plmap"};

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string join(const std::vector<std::string>& ls) {
  std::string s;
  for (const auto& l : ls) s += l + "\n";
  return s;
}

// A TUM folder with the first kFrames frames of the synthetic static sequence, in a
// scratch folder of its own (cases change it freely).
struct Case {
  std::string root;  // scratch folder of the case
  std::string data;  // the dataset folder
  std::string out;   // the output folder, holding "good" outputs of an earlier run
  std::vector<std::string> rgb, depth;  // the list lines (without comments), in order

  explicit Case(const std::string& tag) {
    root = test::scratchDir("badinput_" + tag);
    data = root + "/data";
    out = root + "/out";
    const std::string src = test::syntheticSequence(synth::SceneKind::kStatic, 120);
    fs::create_directories(data + "/rgb");
    fs::create_directories(data + "/depth");
    fs::copy_file(src + "/camera.xml", data + "/camera.xml");
    fs::copy_file(src + "/groundtruth.txt", data + "/groundtruth.txt");
    for (const auto& [list, keep] : {std::pair{"rgb.txt", &rgb}, std::pair{"depth.txt", &depth}}) {
      for (const std::string& l : lines(test::readFile(src + "/" + list))) {
        if (l.empty() || l[0] == '#' || static_cast<int>(keep->size()) >= kFrames) continue;
        keep->push_back(l);
        const std::string file = l.substr(l.find(' ') + 1);
        fs::copy_file(src + "/" + file, data + "/" + file);
      }
    }
    writeLists();
    // Outputs of an earlier, good run: a failing run must leave them as they are.
    fs::create_directories(out);
    for (const char* f : kOutputs)
      writeText(out + "/" + f, std::string("good output of an earlier run: ") + f + "\n");
  }
  void writeLists() const {
    writeText(data + "/rgb.txt", "# color images\n# timestamp filename\n" + join(rgb));
    writeText(data + "/depth.txt", "# depth maps\n# timestamp filename\n" + join(depth));
  }
  std::string file(const std::vector<std::string>& list, size_t i) const {
    return list[i].substr(list[i].find(' ') + 1);
  }
  std::string rgbFile(size_t i) const { return file(rgb, i); }
  std::string depthFile(size_t i) const { return file(depth, i); }
  std::string calib() const { return data + "/camera.xml"; }

  test::CommandResult run(const std::string& extra = "", const std::string& calib_file = "") const {
    return test::runPlslam("run --dataset " + data + " --calib " + (calib_file.empty() ? calib() : calib_file) +
                           " --out " + out + " --sequential --quiet " + extra);
  }
  bool outputsUntouched() const {
    for (const char* f : kOutputs)
      if (test::readFile(out + "/" + f) != std::string("good output of an earlier run: ") + f + "\n") return false;
    for (const auto& e : fs::directory_iterator(out))
      if (e.path().filename().string().find(".tmp.") != std::string::npos) return false;
    return true;
  }
  int statsInt(const std::string& key) const {
    const nlohmann::json stats = test::readJson(out + "/stats.json");
    return stats.is_object() && stats.contains(key) ? stats.at(key).get<int>() : -1;
  }
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A process that died by a signal shows through the shell as -1 or 128 + the signal.
void expectNoCrash(const test::CommandResult& r) {
  EXPECT_GE(r.status, 0) << r.output;
  EXPECT_LT(r.status, 128) << "died by a signal (or a sanitizer report):\n" << r.output;
  EXPECT_FALSE(contains(r.output, "Sanitizer")) << r.output;
}

// A refusal: exit 1 or 2, each of `parts` in the message, the output folder untouched.
void expectRefused(const Case& c, const test::CommandResult& r, const std::vector<std::string>& parts) {
  expectNoCrash(r);
  EXPECT_TRUE(r.status == 1 || r.status == 2) << "exit " << r.status << "\n" << r.output;
  EXPECT_TRUE(contains(r.output, "error: ")) << r.output;
  for (const auto& p : parts) EXPECT_TRUE(contains(r.output, p)) << "message should name '" << p << "':\n" << r.output;
  EXPECT_TRUE(c.outputsUntouched()) << "a failing run changed the outputs of the earlier good run";
}

// A run that goes on: exit 0, each of `parts` in the messages, `skipped` counted in stats.json.
void expectSkipped(const Case& c, const test::CommandResult& r, int skipped, const std::vector<std::string>& parts) {
  expectNoCrash(r);
  EXPECT_EQ(r.status, 0) << r.output;
  for (const auto& p : parts) EXPECT_TRUE(contains(r.output, p)) << "messages should name '" << p << "':\n" << r.output;
  EXPECT_EQ(c.statsInt("skipped_frames"), skipped) << test::readFile(c.out + "/stats.json");
  EXPECT_EQ(c.statsInt("frames"), kFrames - skipped);
}

void overwriteImage(const std::string& path, const cv::Mat& img) { ASSERT_TRUE(cv::imwrite(path, img)) << path; }

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
std::string valueInfo(const std::string& name, const std::vector<int64_t>& dims) {
  std::string shape;
  for (int64_t d : dims) shape += fieldBytes(1, fieldVarint(1, d));
  return fieldBytes(1, name) + fieldBytes(2, fieldBytes(1, fieldVarint(1, 1) + fieldBytes(2, shape)));
}
// A well-framed ONNX model whose one output has a detection-only layout (no mask prototypes).
std::string detectionOnlyModel() {
  std::string graph = fieldBytes(1, fieldBytes(1, "images") + fieldBytes(2, "output0") + fieldBytes(4, "Identity"));
  graph += fieldBytes(2, "det") + fieldBytes(11, valueInfo("images", {1, 3, 64, 64}));
  graph += fieldBytes(12, valueInfo("output0", {1, 84, 8400}));
  return fieldVarint(1, 7) + fieldBytes(7, graph) + fieldBytes(8, fieldVarint(2, 13));
}

}  // namespace

// ---------------------------------------------------------------------- images

TEST(BadInput, CorruptColourPngIsACountedSkip) {
  Case c("corrupt_png");
  writeText(c.data + "/" + c.rgbFile(3), "\x89PNG\r\n\x1a\n but then garbage, not a PNG stream");
  expectSkipped(c, c.run("--log-level warn"), 1, {c.rgbFile(3), "cannot decode", "skipped 1 of"});
}

TEST(BadInput, TruncatedDepthPngIsACountedSkip) {
  Case c("truncated_png");
  const std::string path = c.data + "/" + c.depthFile(5);
  const std::string bytes = test::readFile(path);
  writeText(path, bytes.substr(0, bytes.size() / 2));
  expectSkipped(c, c.run("--log-level warn"), 1, {c.depthFile(5), "skipped 1 of"});
}

TEST(BadInput, ColourAndDepthOfDifferentSizesIsACountedSkip) {
  Case c("size_mismatch");
  const std::string path = c.data + "/" + c.depthFile(2);
  cv::Mat depth = cv::imread(path, cv::IMREAD_UNCHANGED), small;
  cv::resize(depth, small, cv::Size(320, 240), 0, 0, cv::INTER_NEAREST);
  overwriteImage(path, small);
  expectSkipped(c, c.run("--log-level warn"), 1, {c.depthFile(2), "320x240", "640x480"});
}

TEST(BadInput, EveryImageOfAnotherSizeThanTheCameraIsRefused) {
  Case c("wrong_camera");
  std::string xml = test::readFile(c.calib());
  xml = std::regex_replace(xml, std::regex("<image_width>640</image_width>"), "<image_width>320</image_width>");
  xml = std::regex_replace(xml, std::regex("<image_height>480</image_height>"), "<image_height>240</image_height>");
  xml = std::regex_replace(xml, std::regex("<u0>[^<]*</u0>"), "<u0>160</u0>");
  xml = std::regex_replace(xml, std::regex("<v0>[^<]*</v0>"), "<v0>120</v0>");
  writeText(c.root + "/small.xml", xml);
  expectRefused(c, c.run("", c.root + "/small.xml"), {c.data, "none of the", "image size differs from the camera"});
}

TEST(BadInput, EightBitDepthIsRefusedNamingTheFileAndType) {
  Case c("depth_8bit");
  for (int i = 0; i < kFrames; ++i) {
    const std::string path = c.data + "/" + c.depthFile(i);
    cv::Mat d = cv::imread(path, cv::IMREAD_UNCHANGED), d8;
    d.convertTo(d8, CV_8U, 1.0 / 256);
    overwriteImage(path, d8);
  }
  expectRefused(c, c.run("--log-level warn"), {c.depthFile(0), "8-bit", "16-bit", "none of the"});
}

TEST(BadInput, AllZeroDepthIsRefusedAndSomeZeroDepthFramesAreSkipped) {
  {
    Case c("depth_zero_all");
    for (int i = 0; i < kFrames; ++i)
      overwriteImage(c.data + "/" + c.depthFile(i), cv::Mat::zeros(480, 640, CV_16UC1));
    expectRefused(c, c.run("--log-level warn"), {c.depthFile(0), "no valid pixel", "none of the"});
  }
  Case c("depth_zero_some");
  overwriteImage(c.data + "/" + c.depthFile(4), cv::Mat::zeros(480, 640, CV_16UC1));
  expectSkipped(c, c.run("--log-level warn"), 1, {c.depthFile(4), "no valid pixel"});
}

TEST(BadInput, MissingDepthForSomeFramesIsCountedAndLogged) {
  {
    // Listed but absent: a skip with the file named.
    Case c("depth_file_missing");
    fs::remove(c.data + "/" + c.depthFile(6));
    expectSkipped(c, c.run("--log-level warn"), 1, {c.depthFile(6), "not found"});
  }
  // Not listed at all: the colour frames have no depth partner and are left out, said so.
  Case c("depth_unlisted");
  c.depth.erase(c.depth.begin() + 3, c.depth.begin() + 6);
  c.writeLists();
  const auto r = c.run("--log-level warn");
  expectNoCrash(r);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "3 colour frame(s) have no depth")) << r.output;
  EXPECT_EQ(c.statsInt("frames"), kFrames - 3);
}

// ---------------------------------------------------------------------- lists

TEST(BadInput, UnsortedListsGiveTheSameRunAsSortedOnes) {
  Case sorted("lists_sorted");
  const auto a = sorted.run();
  ASSERT_EQ(a.status, 0) << a.output;
  Case c("lists_unsorted");
  std::reverse(c.rgb.begin(), c.rgb.end());
  std::rotate(c.depth.begin(), c.depth.begin() + 5, c.depth.end());
  c.writeLists();
  const auto b = c.run();
  expectNoCrash(b);
  ASSERT_EQ(b.status, 0) << b.output;
  EXPECT_EQ(test::readFile(c.out + "/trajectory.txt"), test::readFile(sorted.out + "/trajectory.txt"))
      << "the lists are sorted by stamp before association";
}

TEST(BadInput, DuplicatedStampsAreLoggedAndTheLastLineKept) {
  Case c("lists_duplicated");
  // A second line for the stamp of frame 2, before the good one: the good line (last) is kept.
  c.rgb.insert(c.rgb.begin() + 2, c.rgb[2].substr(0, c.rgb[2].find(' ')) + " rgb/does_not_exist.png");
  c.writeLists();
  const auto r = c.run("--log-level warn");
  expectNoCrash(r);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "rgb.txt: 1 duplicated timestamp")) << r.output;
  EXPECT_EQ(c.statsInt("frames"), kFrames);
  EXPECT_EQ(c.statsInt("skipped_frames"), 0);
}

TEST(BadInput, ListsWithoutUsableLinesOrPairsAreRefused) {
  {
    Case c("rgb_list_empty");
    writeText(c.data + "/rgb.txt", "# only comments\n\n# here\n");
    expectRefused(c, c.run(), {c.data + "/rgb.txt", "no usable"});
  }
  Case c("no_pairs");
  for (std::string& l : c.depth) l[0] = static_cast<char>(l[0] + 1);  // stamps 1e9 s away from every colour stamp
  c.writeLists();
  expectRefused(c, c.run(), {"depth.txt", "no colour stamp has a depth stamp"});
}

// ---------------------------------------------------------------------- camera, configuration

TEST(BadInput, CameraWithNanOrZeroFocalLengthIsRefusedNamingTheFile) {
  Case c("camera_bad");
  const std::string xml = test::readFile(c.calib());
  writeText(c.root + "/nan.xml", std::regex_replace(xml, std::regex("<px>[^<]*</px>"), "<px>nan</px>"));
  expectRefused(c, c.run("", c.root + "/nan.xml"), {c.root + "/nan.xml", "px"});
  writeText(c.root + "/zero.xml", std::regex_replace(xml, std::regex("<py>[^<]*</py>"), "<py>0</py>"));
  expectRefused(c, c.run("", c.root + "/zero.xml"), {c.root + "/zero.xml", "focal"});
  writeText(c.root + "/cut.xml", xml.substr(0, xml.size() / 2));
  expectRefused(c, c.run("", c.root + "/cut.xml"), {c.root + "/cut.xml", "malformed XML"});
}

TEST(BadInput, ConfigurationWithUnknownKeyOrWrongTypeIsRefused) {
  Case c("config_bad");
  writeText(c.root + "/unknown.yaml", "tracker:\n  min_inliers: 20\n  keyframe_every: 5\n");
  expectRefused(c, c.run("--config " + c.root + "/unknown.yaml"), {c.root + "/unknown.yaml", "tracker.keyframe_every"});
  writeText(c.root + "/type.yaml", "tracker:\n  min_inliers: twenty\n");
  expectRefused(c, c.run("--config " + c.root + "/type.yaml"), {c.root + "/type.yaml", "tracker.min_inliers", "twenty"});
  writeText(c.root + "/list.yaml", "tracker:\n  - min_inliers\n");
  expectRefused(c, c.run("--config " + c.root + "/list.yaml"), {c.root + "/list.yaml", ":2:"});
}

TEST(BadInput, OutputFolderThatIsAFileIsRefusedBeforeTheRun) {
  Case c("out_is_file");
  writeText(c.root + "/taken", "a file, not a folder\n");
  const auto r = test::runPlslam("run --dataset " + c.data + " --calib " + c.calib() + " --out " + c.root +
                                 "/taken --sequential --quiet");
  expectRefused(c, r, {c.root + "/taken", "output folder"});
  EXPECT_EQ(test::readFile(c.root + "/taken"), "a file, not a folder\n");
}

// ---------------------------------------------------------------------- models

TEST(BadInput, ModelThatIsNotOnnxIsRefusedOrSkippedWhenAllowed) {
  Case c("model_not_onnx");
  writeText(c.root + "/model.onnx", "<html>404 Not Found</html>\n");
  expectRefused(c, c.run("--segmenter " + c.root + "/model.onnx"), {c.root + "/model.onnx", "not an ONNX model"});
  const auto r = c.run("--segmenter " + c.root + "/model.onnx --allow-missing-model");
  expectNoCrash(r);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, c.root + "/model.onnx")) << "the fallback must be announced:\n" << r.output;
  EXPECT_TRUE(contains(r.output, "geometry only")) << r.output;
}

TEST(BadInput, ModelWithTheWrongOutputsIsRefused) {
  Case c("model_wrong_outputs");
  writeText(c.root + "/det.onnx", detectionOnlyModel());
  expectRefused(c, c.run("--segmenter " + c.root + "/det.onnx"), {c.root + "/det.onnx", "output"});
}

TEST(BadInput, ClassNamesFileWithABlankLineInsideIsRefused) {
  Case c("classes_bad");
  writeText(c.root + "/names.txt", "person\n\ncar\n");
  // The class list is read before the model (so the model need not exist for this check).
  expectRefused(c, c.run("--segmenter " + c.root + "/model.onnx --classes " + c.root + "/names.txt"),
                {c.root + "/names.txt", "blank"});
}

// ---------------------------------------------------------------------- map files

TEST(BadInput, DamagedOrFutureMapFilesAreRefusedNamingTheFile) {
  Case c("map_bad");
  // A small valid map (the fuzz seed), then three ways a file can go wrong on disk.
  const std::string good = test::readFile(test::sourceDir() + "/fuzz/corpus/map_file/tiny_map");
  ASSERT_GT(good.size(), 100u);
  writeText(c.root + "/cut.plmap", good.substr(0, good.size() * 2 / 3));
  expectRefused(c, c.run("--map " + c.root + "/cut.plmap"), {c.root + "/cut.plmap", "truncated"});
  std::string flipped = good;
  flipped[good.size() - 40] ^= 0x10;
  writeText(c.root + "/flipped.plmap", flipped);
  expectRefused(c, c.run("--map " + c.root + "/flipped.plmap"), {c.root + "/flipped.plmap", "CRC mismatch"});
  std::string future = good;
  future[8] = 9;  // format version, little-endian u32 at offset 8
  writeText(c.root + "/future.plmap", future);
  expectRefused(c, c.run("--map " + c.root + "/future.plmap"), {c.root + "/future.plmap", "version 9"});
  writeText(c.root + "/text.plmap", "trajectory.txt is not a map\n");
  expectRefused(c, c.run("--map " + c.root + "/text.plmap"), {c.root + "/text.plmap"});
}
