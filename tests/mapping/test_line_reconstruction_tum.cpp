// PLY-SLAM's average reconstruction rate on real data: LSD segments on TUM fr1_xyz, fitted
// versus endpoint back-projection. Skipped visibly when ../shared is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "camera/camera_file.h"
#include "core/time.h"
#include "mapping/line_reconstruction.h"
#include "support/test_support.h"

namespace plslam {
namespace {

struct Stamped {
  TimeNs t_ns;
  std::string path;
};

std::vector<Stamped> readList(const std::string& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in.good()) << file;
  std::vector<Stamped> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string stamp, path;
    TimeNs t;
    if (ls >> stamp >> path && parseSecondsStamp(stamp, &t)) out.push_back({t, path});
  }
  return out;
}

PinholeCamera freiburg1() { return loadCameraFile(test::sourceDir() + "/calib/tum_freiburg1.xml"); }

TEST(LineReconstructionTum, FittingBuildsMoreLinesThanEndpointsOnFr1Xyz) {
  PLSLAM_REQUIRE_SHARED("data/tum/fr1_xyz_0-199");
  const std::string dir = test::sharedDir() + "/data/tum/fr1_xyz_0-199/";
  const std::vector<Stamped> rgb = readList(dir + "rgb.txt"), depth = readList(dir + "depth.txt");
  ASSERT_GE(rgb.size(), 200u);
  ASSERT_FALSE(depth.empty());

  const PinholeCamera cam = freiburg1();
  const LineFitOptions opt;
  const cv::Ptr<cv::LineSegmentDetector> lsd = cv::createLineSegmentDetector(cv::LSD_REFINE_STD);
  LineReconstructionRate fit_rate, end_rate;
  std::map<std::string, int> fit_fail, end_fail;
  std::vector<double> fit_rms;
  for (size_t i = 0; i < 200; i += 10) {  // 20 frames over the 6.6 s
    const Stamped* best = &depth.front();
    for (const Stamped& d : depth)
      if (std::llabs(d.t_ns - rgb[i].t_ns) < std::llabs(best->t_ns - rgb[i].t_ns)) best = &d;
    ASSERT_LT(std::llabs(best->t_ns - rgb[i].t_ns), 50'000'000) << "no depth within 50 ms of " << rgb[i].path;
    const cv::Mat gray = cv::imread(dir + rgb[i].path, cv::IMREAD_GRAYSCALE);
    const cv::Mat raw = cv::imread(dir + best->path, cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(gray.empty()) << rgb[i].path;
    ASSERT_EQ(raw.type(), CV_16UC1) << best->path;
    const cv::Mat depth_m = depthToMetres(raw, cam.depth_scale);

    std::vector<cv::Vec4f> lines;
    lsd->detect(gray, lines);
    int used = 0, built_fit = 0, built_end = 0;
    for (const cv::Vec4f& l : lines) {
      const Eigen::Vector2d p(l[0], l[1]), q(l[2], l[3]);
      if ((q - p).norm() <= 30.0) continue;
      ++used;
      LineFitDiagnostics diag;
      if (const auto seg = fitLine3D(p, q, depth_m, cam, opt, &diag)) {
        ++built_fit;
        fit_rms.push_back(seg->rms_m);
      } else {
        ++fit_fail[toString(diag.status)];
      }
      if (backprojectEndpoints(p, q, depth_m, cam, opt, &diag)) ++built_end;
      else ++end_fail[toString(diag.status)];
    }
    fit_rate.add(built_fit, used);
    end_rate.add(built_end, used);
  }
  ASSERT_EQ(fit_rate.frames(), 20);

  ASSERT_FALSE(fit_rms.empty());
  std::nth_element(fit_rms.begin(), fit_rms.begin() + fit_rms.size() / 2, fit_rms.end());
  std::ostringstream report;
  report << "fr1_xyz, 20 frames, " << fit_rate.totalUsed() << " LSD segments > 30 px: average reconstruction rate "
         << "fit " << fit_rate.average() << " (" << fit_rate.totalBuilt() << " built, median inlier rms " << fit_rms[fit_rms.size() / 2] * 1000 << " mm), endpoints "
         << end_rate.average() << " (" << end_rate.totalBuilt() << " built)\n  fit failures:";
  for (const auto& [why, n] : fit_fail) report << " " << why << "=" << n;
  report << "\n  endpoint failures:";
  for (const auto& [why, n] : end_fail) report << " " << why << "=" << n;
  std::printf("%s\n", report.str().c_str());
  RecordProperty("fit_rate", std::to_string(fit_rate.average()));
  RecordProperty("endpoint_rate", std::to_string(end_rate.average()));

  EXPECT_GT(fit_rate.average(), end_rate.average());
}

}  // namespace
}  // namespace plslam
