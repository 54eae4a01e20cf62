#include <gtest/gtest.h>

#include <fstream>
#include <utility>
#include <vector>
#include <visp3/core/vpXmlParserCamera.h>

#include "camera/camera_file.h"
#include "core/error.h"
#include "core/log.h"
#include "support/test_support.h"

using namespace plslam;

namespace {
std::string calib(const std::string& name) { return test::sourceDir() + "/calib/" + name; }

// Expects parseCameraFile(content) to throw an error whose message has every `needle`.
void expectRefused(const std::string& content, std::initializer_list<const char*> needles) {
  try {
    parseCameraFile(content, "bad.xml");
    FAIL() << "accepted:\n" << content;
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.xml"), std::string::npos) << msg;
    for (const char* n : needles) EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
  }
}

const char* kGood = R"(<?xml version="1.0"?>
<root><camera><name>c</name><image_width>640</image_width><image_height>480</image_height>
<model><type>perspectiveProjWithoutDistortion</type><px>500</px><py>501</py><u0>320</u0><v0>240</v0></model>
<additional_information><rgbd><depth_scale>1000</depth_scale></rgbd></additional_information></camera></root>)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}
}  // namespace

TEST(CameraFile, ShippedFilesLoadAndAgreeWithVisp) {
  struct Expect {
    const char* file;
    double fx, fy, cy, scale, k1;
  };
  // ICL-NUIM as published: fy = -480.
  for (const Expect& e : {Expect{"tum_freiburg1.xml", 517.3, 516.5, 255.3, 5000, 0.2624},
                          Expect{"tum_freiburg2.xml", 520.9, 521.0, 249.7, 5000, 0.2312},
                          Expect{"tum_freiburg3.xml", 535.4, 539.2, 247.6, 5000, 0},
                          Expect{"icl_nuim.xml", 481.2, -480.0, 239.5, 5000, 0},
                          Expect{"d435i_640x480.xml", 615.0, 615.0, 240.0, 1000, 0}}) {
    SCOPED_TRACE(e.file);
    const PinholeCamera cam = loadCameraFile(calib(e.file));
    EXPECT_EQ(cam.width, 640);
    EXPECT_EQ(cam.height, 480);
    EXPECT_DOUBLE_EQ(cam.fx, e.fx);
    EXPECT_DOUBLE_EQ(cam.fy, e.fy);
    EXPECT_DOUBLE_EQ(cam.cy, e.cy);
    EXPECT_DOUBLE_EQ(cam.depth_scale, e.scale);
    EXPECT_DOUBLE_EQ(cam.dist[0], e.k1);
    // ViSP's own parser reads the same file without complaint.
    vpXmlParserCamera parser;
    vpCameraParameters vp;
    ASSERT_EQ(parser.parse(vp, calib(e.file), cam.name, vpCameraParameters::perspectiveProjWithoutDistortion, 640, 480),
              vpXmlParserCamera::SEQUENCE_OK);
    EXPECT_DOUBLE_EQ(vp.get_px(), cam.fx);
    EXPECT_DOUBLE_EQ(vp.get_py(), cam.fy);
    EXPECT_DOUBLE_EQ(vp.get_u0(), cam.cx);
    EXPECT_DOUBLE_EQ(vp.get_v0(), cam.cy);
  }
}

TEST(CameraFile, SaveLoadRoundTrip) {
  PinholeCamera cam = loadCameraFile(calib("tum_freiburg1.xml"));
  cam.name = "roundtrip";
  const std::string path = test::scratchDir("camera") + "/cam.xml";
  saveCameraFile(path, cam, "test");
  const PinholeCamera back = loadCameraFile(path);
  EXPECT_EQ(back.name, "roundtrip");
  EXPECT_DOUBLE_EQ(back.fx, cam.fx);
  EXPECT_DOUBLE_EQ(back.cx, cam.cx);
  for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(back.dist[i], cam.dist[i]);
  EXPECT_DOUBLE_EQ(back.depth_scale, cam.depth_scale);
}

TEST(CameraFile, NegativeFocalLengthsRoundTripAndViSPReadsThem) {
  // Signed focal lengths are written as they are, read back by plslam and by ViSP's parser.
  PinholeCamera cam = loadCameraFile(calib("tum_freiburg1.xml"));
  cam.name = "mirrored";
  cam.fx = -cam.fx;
  cam.fy = -cam.fy;
  cam.cx = 639 - cam.cx;
  cam.cy = 479 - cam.cy;
  const std::string path = test::scratchDir("camera") + "/negative.xml";
  saveCameraFile(path, cam, "mirrored freiburg1");
  const PinholeCamera back = loadCameraFile(path);
  EXPECT_DOUBLE_EQ(back.fx, cam.fx);
  EXPECT_DOUBLE_EQ(back.fy, cam.fy);
  EXPECT_DOUBLE_EQ(back.cx, cam.cx);
  EXPECT_DOUBLE_EQ(back.cy, cam.cy);
  for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(back.dist[i], cam.dist[i]);
  const Eigen::Vector3d p(0.2, -0.3, 1.7);
  EXPECT_LT((back.project(p) - cam.project(p)).norm(), 1e-9);
  vpXmlParserCamera parser;
  vpCameraParameters vp;
  ASSERT_EQ(parser.parse(vp, path, "mirrored", vpCameraParameters::perspectiveProjWithoutDistortion, 640, 480),
            vpXmlParserCamera::SEQUENCE_OK);
  EXPECT_DOUBLE_EQ(vp.get_px(), cam.fx);
  EXPECT_DOUBLE_EQ(vp.get_py(), cam.fy);
  // Only the sign of py differs from a normal ViSP file.
  EXPECT_DOUBLE_EQ(parseCameraFile(replaced(kGood, "<py>501</py>", "<py>-501</py>"), "neg.xml").fy, -501.0);
}

TEST(CameraFile, ByteOrderMarkAndCharacterReferencesAreRead) {
  // Files written by Windows editors start with a UTF-8 byte order mark; &#NN; and &#xNN;
  // are ordinary XML.
  std::string content = "\xEF\xBB\xBF" + replaced(kGood, "<name>c</name>", "<name>&#x61;&#98;&lt;</name>");
  content = replaced(content, "<px>500</px>", "<px>&#53;00</px>");
  const PinholeCamera cam = parseCameraFile(content, "bom.xml");
  EXPECT_EQ(cam.name, "ab<");
  EXPECT_DOUBLE_EQ(cam.fx, 500.0);
}

TEST(CameraFile, NamesWithMarkupCharactersRoundTripAndViSPReadsThem) {
  PinholeCamera cam = loadCameraFile(calib("tum_freiburg1.xml"));
  cam.name = "a<b & \"c\" 'd' >";
  const std::string path = test::scratchDir("camera") + "/escaped.xml";
  saveCameraFile(path, cam, "a comment -- with <markup> & a dash at the end -");
  EXPECT_EQ(loadCameraFile(path, cam.name).name, cam.name);
  vpXmlParserCamera parser;
  vpCameraParameters vp;
  ASSERT_EQ(parser.parse(vp, path, cam.name, vpCameraParameters::perspectiveProjWithoutDistortion, 640, 480),
            vpXmlParserCamera::SEQUENCE_OK);
  EXPECT_DOUBLE_EQ(vp.get_px(), cam.fx);
}

TEST(CameraFile, ViSPFileWithoutRgbdAssumesMillimetresAndWarnsSo) {
  const std::string content = replaced(kGood, "<additional_information><rgbd><depth_scale>1000</depth_scale></rgbd></additional_information>", "");
  std::vector<std::pair<LogLevel, std::string>> logged;
  setLogSink([&](LogLevel level, const std::string&, const std::string& m) { logged.emplace_back(level, m); });
  const double scale = parseCameraFile(content, "visp.xml").depth_scale;
  const double with_rgbd = parseCameraFile(kGood, "plslam.xml").depth_scale;
  setLogSink(nullptr);
  EXPECT_DOUBLE_EQ(scale, 1000.0);
  EXPECT_DOUBLE_EQ(with_rgbd, 1000.0);
  // One warning (shown at the default level), naming the file and the TUM value; none for the
  // file that says its scale.
  ASSERT_EQ(logged.size(), 1u);
  EXPECT_EQ(logged[0].first, LogLevel::kWarn);
  EXPECT_NE(logged[0].second.find("visp.xml"), std::string::npos) << logged[0].second;
  EXPECT_NE(logged[0].second.find("5000"), std::string::npos) << logged[0].second;
}

TEST(CameraFile, MissingFileIsRefusedNamingIt) {
  try {
    loadCameraFile("/nonexistent/cam.xml");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/cam.xml"), std::string::npos);
  }
}

TEST(CameraFile, MalformedFilesAreRefusedWithTheProblem) {
  EXPECT_NO_THROW(parseCameraFile(kGood, "good.xml"));
  // XML errors are pugixml's descriptions, with the line.
  expectRefused("", {"malformed XML", "No document element"});
  expectRefused("<root><camera>", {"bad.xml:1:", "mismatch"});
  expectRefused(replaced(kGood, "</model>", "</modelx>"), {"bad.xml:3:", "mismatch"});
  expectRefused(replaced(kGood, "<px>500</px>", "<px>5&bogus;00</px>"), {"bad.xml:3:", "not a number"});  // unknown entity: left as text
  expectRefused(replaced(kGood, "<root>", "<toor>").replace(std::string(kGood).rfind("</root>") , 7, "</toor>"), {"<root>"});
  expectRefused(replaced(kGood, "<px>500</px>", "<px>abc</px>"), {"px", "not a number"});
  EXPECT_NO_THROW(parseCameraFile(replaced(kGood, "<px>500</px>", "<px>-500</px>"), "negative.xml"));
  expectRefused(replaced(kGood, "<py>501</py>", "<py>0</py>"), {"focal"});
  expectRefused(replaced(kGood, "<py>501</py>", "<py>-0</py>"), {"focal"});
  expectRefused(replaced(kGood, "<px>500</px>", "<px>-1e-9</px>"), {"focal"});
  expectRefused(replaced(kGood, "<px>500</px>", "<px>-1e999</px>"), {"px"});
  expectRefused(replaced(kGood, "<py>501</py>", "<py>nan</py>"), {"py", "not a number"});
  expectRefused(replaced(kGood, "<py>501</py>", "<py>1e999</py>"), {"py"});
  expectRefused(replaced(kGood, "<px>500</px>", ""), {"px"});
  expectRefused(replaced(kGood, "<u0>320</u0>", "<u0>2000</u0>"), {"principal point"});
  expectRefused(replaced(kGood, "<image_width>640</image_width>", "<image_width>6.5</image_width>"), {"image_width"});
  // Beyond long long: was converted before the range check (undefined; found by fuzzing).
  expectRefused(replaced(kGood, "<image_width>640</image_width>", "<image_width>6" + std::string(40, '8') + "</image_width>"),
                {"image_width", "whole number"});
  expectRefused(replaced(kGood, "perspectiveProjWithoutDistortion", "fisheye"), {"fisheye"});
  expectRefused(replaced(kGood, "<depth_scale>1000</depth_scale>", "<depth_scale>-1</depth_scale>"), {"depth scale"});
  EXPECT_THROW(parseCameraFile(kGood, "c.xml", "other_name"), IoError);
}

TEST(CameraFile, ImageSizeMismatchIsNamed) {
  const PinholeCamera cam = parseCameraFile(kGood, "good.xml");
  EXPECT_NO_THROW(checkImageSize(cam, 640, 480, "rgb/1.png"));
  try {
    checkImageSize(cam, 320, 240, "rgb/1.png");
    FAIL();
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("rgb/1.png"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("320x240"), std::string::npos);
  }
}
