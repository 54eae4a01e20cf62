#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/error.h"
#include "core/log.h"
#include "camera/camera_file.h"
#include "io/dataset.h"
#include "support/test_support.h"

using namespace plslam;
namespace fs = std::filesystem;

namespace {

PinholeCamera smallCamera() {
  PinholeCamera c;
  c.name = "test64x48";
  c.width = 64;
  c.height = 48;
  c.fx = c.fy = 50;
  c.cx = 31.5;
  c.cy = 23.5;
  c.depth_scale = 5000;
  return c;
}

cv::Mat colourImage(int w = 64, int h = 48) {
  cv::Mat img(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at<cv::Vec3b>(y, x) = cv::Vec3b(x * 3 % 256, y * 5 % 256, 100);
  return img;
}

/// Raw depth 5000 + 10 x + y (about 1 m), 0 (no reading) at pixel (0, 0).
cv::Mat depthImage(int w = 64, int h = 48) {
  cv::Mat img(h, w, CV_16UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at<uint16_t>(y, x) = static_cast<uint16_t>(5000 + 10 * x + y);
  img.at<uint16_t>(0, 0) = 0;
  return img;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

/// A TUM folder under construction: images are written as they are added, lists at the end.
class TumFolder {
 public:
  explicit TumFolder(std::string dir) : dir_(std::move(dir)) {
    fs::create_directories(dir_ + "/rgb");
    fs::create_directories(dir_ + "/depth");
  }
  const std::string& dir() const { return dir_; }

  /// Lists rgb/<stamp>.png; writes `img` unless it is empty (a listed but missing file).
  void colour(const std::string& stamp, const cv::Mat& img) {
    const std::string rel = "rgb/" + stamp + ".png";
    if (!img.empty()) cv::imwrite(dir_ + "/" + rel, img);
    rgb_ << stamp << " " << rel << "\n";
  }
  void colour(const std::string& stamp) { colour(stamp, colourImage()); }
  void depth(const std::string& stamp, const cv::Mat& img) {
    const std::string rel = "depth/" + stamp + ".png";
    if (!img.empty()) cv::imwrite(dir_ + "/" + rel, img);
    depth_ << stamp << " " << rel << "\n";
  }
  void depth(const std::string& stamp) { depth(stamp, depthImage()); }
  void rawRgbLine(const std::string& line) { rgb_ << line << "\n"; }

  void writeLists() const {
    writeText(dir_ + "/rgb.txt", "# color images\n# timestamp filename\n" + rgb_.str());
    writeText(dir_ + "/depth.txt", "# depth maps\n# timestamp filename\n" + depth_.str());
  }

 private:
  std::string dir_;
  std::ostringstream rgb_, depth_;
};

/// Captures log messages for the duration of a test.
class DatasetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setLogSink([this](LogLevel, const std::string&, const std::string& m) { messages_.push_back(m); });
  }
  void TearDown() override { setLogSink(nullptr); }
  bool logged(const std::string& needle) const {
    return std::any_of(messages_.begin(), messages_.end(),
                       [&](const std::string& m) { return m.find(needle) != std::string::npos; });
  }
  std::vector<std::string> messages_;
};

std::string ioErrorMessage(const std::string& dir, const DatasetOptions& options = {}) {
  try {
    TumDataset::open(dir, smallCamera(), options);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_F(DatasetTest, AssociatesColourAndDepthLikeAssociatePy) {
  TumFolder f(test::scratchDir("io"));
  for (const char* s : {"1.000000", "1.033000", "1.066000", "1.100000", "2.000000", "2.010000"}) f.colour(s);
  f.depth("1.005000");  // -> 1.000
  f.depth("1.040000");  // -> 1.033 (0.007)
  f.depth("1.063000");  // -> 1.066 (0.003; 0.030 from 1.033 would be outside the window anyway)
  f.depth("1.130000");  // 0.030 from 1.100: not paired
  f.depth("2.009000");  // 2.010 (0.001) wins over 2.000 (0.009): each stamp used once
  f.writeLists();

  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  ASSERT_EQ(ds.size(), 4u);
  const std::vector<std::pair<TimeNs, TimeNs>> expected = {{1'000'000'000, 1'005'000'000},
                                                           {1'033'000'000, 1'040'000'000},
                                                           {1'066'000'000, 1'063'000'000},
                                                           {2'010'000'000, 2'009'000'000}};
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(ds.entries()[i].t_rgb_ns, expected[i].first) << i;
    EXPECT_EQ(ds.entries()[i].t_depth_ns, expected[i].second) << i;
  }
  EXPECT_EQ(ds.listReport().rgb_listed, 6);
  EXPECT_EQ(ds.listReport().depth_listed, 5);
  EXPECT_EQ(ds.listReport().rgb_unpaired, 2);
  EXPECT_EQ(ds.listReport().depth_unpaired, 1);
  EXPECT_FALSE(ds.hasGroundtruth());

  RgbdFrame frame;
  ASSERT_EQ(ds.load(1, &frame), FrameStatus::kOk);
  EXPECT_EQ(frame.t_ns, 1'033'000'000);
  EXPECT_EQ(frame.index, 1);
  EXPECT_EQ(frame.name, "rgb/1.033000.png");
  ASSERT_EQ(frame.bgr.type(), CV_8UC3);
  EXPECT_EQ(frame.bgr.at<cv::Vec3b>(10, 20), colourImage().at<cv::Vec3b>(10, 20));
  ASSERT_EQ(frame.depth_m.type(), CV_32FC1);
  EXPECT_NEAR(frame.depth_m.at<float>(10, 20), (5000 + 200 + 10) / 5000.0, 1e-6);
  EXPECT_TRUE(std::isnan(frame.depth_m.at<float>(0, 0)));
  EXPECT_TRUE(frame.instance_ids.empty());

  int n = 0;
  while (ds.next(&frame)) EXPECT_EQ(frame.index, n++);
  EXPECT_EQ(n, 4);
  EXPECT_EQ(ds.count(FrameStatus::kOk), 4);
  EXPECT_EQ(ds.skippedTotal(), 0);
}

TEST_F(DatasetTest, ImageSizeDifferentFromCameraIsACountedSkip) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0", colourImage());
  f.colour("2.0", colourImage(80, 48));
  f.colour("3.0", colourImage());
  for (const char* s : {"1.0", "2.0", "3.0"}) f.depth(s);
  f.writeLists();
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  ASSERT_EQ(ds.size(), 3u);
  RgbdFrame frame;
  std::vector<int> seen;
  while (ds.next(&frame)) seen.push_back(frame.index);
  EXPECT_EQ(seen, (std::vector<int>{0, 2}));
  EXPECT_EQ(ds.count(FrameStatus::kSizeMismatch), 1);
  EXPECT_EQ(ds.skippedTotal(), 1);
  EXPECT_TRUE(logged("rgb/2.0.png")) << "the skip is logged with the file name";
  // Loading the frame again does not count it twice.
  std::string reason;
  EXPECT_EQ(ds.load(1, &frame, &reason), FrameStatus::kSizeMismatch);
  EXPECT_NE(reason.find("80x48"), std::string::npos) << reason;
  EXPECT_EQ(ds.count(FrameStatus::kSizeMismatch), 1);
}

TEST_F(DatasetTest, EightBitDepthIsACountedSkip) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0");
  f.colour("2.0");
  f.depth("1.0", cv::Mat(48, 64, CV_8UC1, cv::Scalar(40)));
  f.depth("2.0");
  f.writeLists();
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  RgbdFrame frame;
  std::string reason;
  EXPECT_EQ(ds.load(0, &frame, &reason), FrameStatus::kBadDepthType);
  EXPECT_NE(reason.find("depth/1.0.png"), std::string::npos) << reason;
  EXPECT_EQ(ds.load(1, &frame), FrameStatus::kOk);
  EXPECT_EQ(ds.count(FrameStatus::kBadDepthType), 1);
  EXPECT_TRUE(logged("depth/1.0.png"));
}

TEST_F(DatasetTest, MissingOrUndecodableFileIsACountedSkip) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0", cv::Mat());  // listed, never written
  f.colour("2.0");
  f.colour("3.0");
  for (const char* s : {"1.0", "2.0", "3.0"}) f.depth(s);
  f.writeLists();
  writeText(f.dir() + "/rgb/3.0.png", "this is not a PNG");
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  RgbdFrame frame;
  ASSERT_TRUE(ds.next(&frame));
  EXPECT_EQ(frame.index, 1);
  EXPECT_FALSE(ds.next(&frame));
  EXPECT_EQ(ds.count(FrameStatus::kMissingFile), 1);
  EXPECT_EQ(ds.count(FrameStatus::kUnreadable), 1);
  EXPECT_EQ(ds.skippedTotal(), 2);
  EXPECT_TRUE(logged("rgb/1.0.png"));
  EXPECT_TRUE(logged("rgb/3.0.png"));
}

TEST_F(DatasetTest, GreyColourIsConvertedOtherTypesSkipped) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0", cv::Mat(48, 64, CV_8UC1, cv::Scalar(77)));
  f.colour("2.0", cv::Mat(48, 64, CV_16UC3, cv::Scalar(1, 2, 3)));
  f.depth("1.0");
  f.depth("2.0");
  f.writeLists();
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  RgbdFrame frame;
  ASSERT_EQ(ds.load(0, &frame), FrameStatus::kOk);
  ASSERT_EQ(frame.bgr.type(), CV_8UC3);
  EXPECT_EQ(frame.bgr.at<cv::Vec3b>(5, 5), cv::Vec3b(77, 77, 77));
  EXPECT_EQ(ds.load(1, &frame), FrameStatus::kBadColourType);

  DatasetOptions strict;
  strict.convert_grey = false;
  TumDataset ds2 = TumDataset::open(f.dir(), smallCamera(), strict);
  EXPECT_EQ(ds2.load(0, &frame), FrameStatus::kBadColourType);
}

TEST_F(DatasetTest, MissingRgbListIsAnIoErrorNamingTheFile) {
  const std::string dir = test::scratchDir("io");
  writeText(dir + "/depth.txt", "1.0 depth/1.0.png\n");
  const std::string msg = ioErrorMessage(dir);
  EXPECT_NE(msg.find("rgb.txt"), std::string::npos) << msg;

  const std::string missing = dir + "/no_such_folder";
  EXPECT_NE(ioErrorMessage(missing).find("no_such_folder"), std::string::npos);
}

TEST_F(DatasetTest, MissingDepthListIsAnIoErrorNamingTheFile) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0");
  f.writeLists();
  fs::remove(f.dir() + "/depth.txt");
  EXPECT_NE(ioErrorMessage(f.dir()).find("depth.txt"), std::string::npos);
}

TEST_F(DatasetTest, UnparsableListLinesAreCountedAndSkipped) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0");
  f.rawRgbLine("not-a-stamp rgb/x.png");
  f.rawRgbLine("1.5");  // no file name
  f.rawRgbLine("");
  f.colour("2.0");
  f.depth("1.0");
  f.depth("2.0");
  f.writeLists();
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  EXPECT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds.listReport().lines_skipped, 2);
  EXPECT_TRUE(logged("rgb.txt"));
}

TEST_F(DatasetTest, NothingAssociatedIsAnIoError) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0");
  f.depth("1.5");
  f.writeLists();
  const std::string msg = ioErrorMessage(f.dir());
  EXPECT_NE(msg.find("rgb.txt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("depth.txt"), std::string::npos) << msg;
}

TEST_F(DatasetTest, MaxFramesKeepsTheFirstFrames) {
  TumFolder f(test::scratchDir("io"));
  for (const char* s : {"1.0", "2.0", "3.0", "4.0"}) {
    f.colour(s);
    f.depth(s);
  }
  f.writeLists();
  DatasetOptions o;
  o.max_frames = 3;
  TumDataset ds = TumDataset::open(f.dir(), smallCamera(), o);
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_EQ(ds.stamps().back(), 3 * kNsPerSecond);
  EXPECT_EQ(ds.listReport().cut_by_max_frames, 1);
}

TEST_F(DatasetTest, GroundTruthIsLoadedWhenPresent) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0");
  f.depth("1.0");
  f.writeLists();
  writeText(f.dir() + "/groundtruth.txt", "# gt\n1.0 1 2 3 0 0 0 1\n1.01 1.1 2 3 0 0 0 1\n");
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  ASSERT_EQ(ds.groundtruth().size(), 2u);
  EXPECT_DOUBLE_EQ(ds.groundtruth()[1].T_w_c.translation().x(), 1.1);
}

TEST_F(DatasetTest, InstanceMasksAreLoadedByClosestStamp) {
  TumFolder f(test::scratchDir("io"));
  for (const char* s : {"1.000000", "2.000000", "3.000000"}) {
    f.colour(s);
    f.depth(s);
  }
  f.writeLists();
  fs::create_directories(f.dir() + "/masks");
  cv::Mat mask(48, 64, CV_16UC1, cv::Scalar(0));
  mask(cv::Rect(10, 10, 20, 15)).setTo(3);
  mask(cv::Rect(40, 5, 10, 30)).setTo(7);
  cv::imwrite(f.dir() + "/masks/a.png", mask);
  cv::imwrite(f.dir() + "/masks/b.png", cv::Mat(48, 64, CV_16UC1, cv::Scalar(9)));
  // 1.0 -> a (0.001 away); 2.0 -> b (0.015 away); 3.0 has none within 0.02 s.
  writeText(f.dir() + "/masks.txt", "# instance masks\n1.001000 masks/a.png\n2.015000 masks/b.png\n3.050000 masks/b.png\n");
  writeText(f.dir() + "/masks/instances.txt", "# instance_id class_id class_name\n3 0 person\n7 56 potted plant\n");

  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  EXPECT_EQ(ds.listReport().masks_listed, 3);
  EXPECT_EQ(ds.listReport().frames_without_mask, 1);
  ASSERT_EQ(ds.instanceLabels().size(), 2u);
  EXPECT_EQ(ds.instanceLabels()[1].instance_id, 7);
  EXPECT_EQ(ds.instanceLabels()[1].class_id, 56);
  EXPECT_EQ(ds.instanceLabels()[1].class_name, "potted plant");

  RgbdFrame frame;
  ASSERT_EQ(ds.load(0, &frame), FrameStatus::kOk);
  ASSERT_EQ(frame.instance_ids.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(frame.instance_ids, mask, cv::NORM_INF), 0.0);
  ASSERT_EQ(ds.load(1, &frame), FrameStatus::kOk);
  EXPECT_EQ(frame.instance_ids.at<uint16_t>(0, 0), 9);
  ASSERT_EQ(ds.load(2, &frame), FrameStatus::kOk);
  EXPECT_TRUE(frame.instance_ids.empty());

  DatasetOptions no_masks;
  no_masks.load_masks = false;
  TumDataset plain = TumDataset::open(f.dir(), smallCamera(), no_masks);
  ASSERT_EQ(plain.load(0, &frame), FrameStatus::kOk);
  EXPECT_TRUE(frame.instance_ids.empty());
}

TEST_F(DatasetTest, EightBitMaskIsACountedSkip) {
  TumFolder f(test::scratchDir("io"));
  f.colour("1.0");
  f.depth("1.0");
  f.writeLists();
  fs::create_directories(f.dir() + "/masks");
  cv::imwrite(f.dir() + "/masks/a.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(1)));
  writeText(f.dir() + "/masks.txt", "1.0 masks/a.png\n");
  TumDataset ds = TumDataset::open(f.dir(), smallCamera());
  RgbdFrame frame;
  EXPECT_EQ(ds.load(0, &frame), FrameStatus::kBadMaskType);
  EXPECT_EQ(ds.count(FrameStatus::kBadMaskType), 1);
}

TEST_F(DatasetTest, IclNuimAssociationsLayoutIsRead) {
  // The published ICL-NUIM archives: "t depth/x.png t rgb/x.png", frame numbers as stamps,
  // ground truth in <name>.gt.freiburg, no rgb.txt/depth.txt.
  const std::string dir = test::scratchDir("io");
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  std::ostringstream assoc;
  for (int i = 0; i < 3; ++i) {
    cv::imwrite(str(dir, "/rgb/", i, ".png"), colourImage());
    cv::Mat d = depthImage();
    d.setTo(5000 * (i + 1));  // i + 1 metres at 5000 units per metre
    cv::imwrite(str(dir, "/depth/", i, ".png"), d);
    assoc << i << " depth/" << i << ".png " << i << " rgb/" << i << ".png\n";
  }
  writeText(dir + "/associations.txt", assoc.str());
  writeText(dir + "/livingRoom0.gt.freiburg", "0 0 0 0 0 0 0 1\n1 0.1 0 0 0 0 0 1\n2 0.2 0 0 0 0 0 1\n");

  TumDataset ds = TumDataset::open(dir, smallCamera());
  EXPECT_EQ(ds.listReport().layout, DatasetListReport::Layout::kAssociations);
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_EQ(ds.entries()[2].rgb_path, "rgb/2.png");
  EXPECT_EQ(ds.entries()[2].depth_path, "depth/2.png");
  EXPECT_EQ(ds.groundtruth().size(), 3u);
  RgbdFrame frame;
  ASSERT_EQ(ds.load(2, &frame), FrameStatus::kOk);
  EXPECT_EQ(frame.t_ns, 2 * kNsPerSecond);
  EXPECT_NEAR(frame.depth_m.at<float>(20, 20), 3.0, 1e-6);

  // associate.py's output order, colour first, is read the same way.
  std::ostringstream colour_first;
  for (int i = 0; i < 3; ++i) colour_first << i << " rgb/" << i << ".png " << i << " depth/" << i << ".png\n";
  writeText(dir + "/associations.txt", colour_first.str());
  TumDataset ds2 = TumDataset::open(dir, smallCamera());
  ASSERT_EQ(ds2.size(), 3u);
  EXPECT_EQ(ds2.entries()[1].rgb_path, "rgb/1.png");
  ASSERT_EQ(ds2.load(1, &frame), FrameStatus::kOk);
  EXPECT_NEAR(frame.depth_m.at<float>(20, 20), 2.0, 1e-6);
}

namespace {
/// Independent re-implementation of associate.py for the real-data check: every pair
/// below 0.02 s, sorted by difference, taken greedily.
size_t referenceAssociationCount(const std::string& rgb_txt, const std::string& depth_txt) {
  auto stamps = [](const std::string& path) {
    std::vector<double> out;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      out.push_back(std::stod(line.substr(0, line.find(' '))));
    }
    return out;
  };
  const std::vector<double> a = stamps(rgb_txt), b = stamps(depth_txt);
  std::vector<std::tuple<double, size_t, size_t>> c;
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j)
      if (std::abs(a[i] - b[j]) < 0.02) c.emplace_back(std::abs(a[i] - b[j]), i, j);
  std::sort(c.begin(), c.end());
  std::vector<bool> ua(a.size()), ub(b.size());
  size_t n = 0;
  for (const auto& [d, i, j] : c) {
    if (ua[i] || ub[j]) continue;
    ua[i] = ub[j] = true;
    ++n;
  }
  return n;
}
}  // namespace

TEST(DatasetReal, Fr1XyzFirst200Frames) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr1_xyz_0-199");
  const std::string dir = test::sharedDir() + "/data/tum/fr1_xyz_0-199";
  // The shipped camera file, so the test reads the data the way users do.
  const PinholeCamera cam = loadCameraFile(test::sourceDir() + "/calib/tum_freiburg1.xml");

  TumDataset ds = TumDataset::open(dir, cam);
  EXPECT_EQ(ds.size(), referenceAssociationCount(dir + "/rgb.txt", dir + "/depth.txt"));
  EXPECT_GE(ds.size(), 190u);
  EXPECT_LE(ds.size(), 200u);
  ASSERT_TRUE(ds.hasGroundtruth());
  EXPECT_LE(ds.groundtruth().front().t_ns, ds.stamps().front());
  EXPECT_GE(ds.groundtruth().back().t_ns, ds.stamps().back());

  RgbdFrame frame;
  int loaded = 0;
  while (ds.next(&frame)) {
    ++loaded;
    double lo = 0, hi = 0;
    cv::Mat valid = frame.depth_m == frame.depth_m;  // false at NaN
    ASSERT_GT(cv::countNonZero(valid), 0) << frame.name;
    cv::minMaxLoc(frame.depth_m, &lo, &hi, nullptr, nullptr, valid);
    EXPECT_GT(lo, 0.0) << frame.name;
    EXPECT_LT(hi, 10.0) << frame.name;
  }
  EXPECT_EQ(loaded, static_cast<int>(ds.size()));
  EXPECT_EQ(ds.skippedTotal(), 0);
}
