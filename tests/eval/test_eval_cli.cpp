// Runs the built `plslam eval` as a user would.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>

#include "io/trajectory_file.h"
#include "support/test_support.h"

using namespace plslam;

namespace {

struct CliRun {
  int status = -1;  ///< exit code
  std::string out;
};

CliRun run(const std::string& args) {
  const test::CommandResult r = test::runPlslam("eval " + args, false);
  return {r.status, r.output};
}

/// The number after "key": at or after `from` in a JSON text; NaN when absent.
double jsonNumber(const std::string& json, const std::string& key, size_t from = 0) {
  const size_t k = json.find("\"" + key + "\":", from);
  if (k == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + k + key.size() + 3, nullptr);
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST(EvalCli, JsonOnTheReferencePairGivesTheBenchmarkFigures) {
  PLSLAM_REQUIRE_SHARED("data/trajectories");
  const std::string dir = test::sharedDir() + "/data/trajectories/";
  const CliRun r = run("--gt " + quoted(dir + "freiburg1_xyz-groundtruth.txt") + " --est " +
                    quoted(dir + "freiburg1_xyz-rgbdslam.txt") + " --json 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.out;
  // Exactly one JSON object: '{' first, its matching '}' last.
  const size_t b = r.out.find_first_not_of(" \n"), e = r.out.find_last_not_of(" \n");
  ASSERT_NE(b, std::string::npos);
  EXPECT_EQ(r.out[b], '{');
  EXPECT_EQ(r.out[e], '}');
  int depth = 0;
  for (size_t i = b; i <= e; ++i) {
    depth += r.out[i] == '{' ? 1 : r.out[i] == '}' ? -1 : 0;
    if (i < e) {
      ASSERT_GT(depth, 0) << "the object closes before the end of the output";
    }
  }
  EXPECT_EQ(depth, 0);

  EXPECT_EQ(jsonNumber(r.out, "pairs"), 786);
  const size_t ate = r.out.find("\"ate\"");
  ASSERT_NE(ate, std::string::npos);
  EXPECT_NEAR(jsonNumber(r.out, "rmse", ate), 0.013473, 1e-5);
  EXPECT_NEAR(jsonNumber(r.out, "mean", ate), 0.012029, 1e-5);
  EXPECT_NEAR(jsonNumber(r.out, "median", ate), 0.011176, 1e-5);
  const size_t rpe = r.out.find("\"rpe\"");
  ASSERT_NE(rpe, std::string::npos);
  EXPECT_GT(jsonNumber(r.out, "pairs", rpe), 0);
  EXPECT_NEAR(jsonNumber(r.out, "trans_rmse", rpe), 0.021217, 1e-5);
  EXPECT_NEAR(jsonNumber(r.out, "rot_rmse_deg", rpe), 0.934480, 1e-5);
  EXPECT_FALSE(std::isnan(jsonNumber(r.out, "trans_mean", rpe)));
  EXPECT_FALSE(std::isnan(jsonNumber(r.out, "rot_mean_deg", rpe)));
}

TEST(EvalCli, PlotWritesAPngOfTheDocumentedSize) {
  PLSLAM_REQUIRE_SHARED("data/trajectories");
  const std::string dir = test::sharedDir() + "/data/trajectories/";
  const std::string png = test::scratchDir("eval") + "/ate.png";
  const CliRun r = run("--gt " + quoted(dir + "fr2_desk_groundtruth.txt") + " --est " + quoted(dir + "fr2_desk_ORB.txt") +
                    " --plot " + quoted(png) + " 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("ATE"), std::string::npos) << r.out;  // the text summary by default
  const cv::Mat img = cv::imread(png, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1000);  // PlotOptions defaults
  EXPECT_EQ(img.rows, 800);
  ASSERT_EQ(img.type(), CV_8UC3);
  // Something coloured was drawn (the estimate and the colour bar), not only grey and white.
  int coloured = 0;
  for (auto it = img.begin<cv::Vec3b>(); it != img.end<cv::Vec3b>(); ++it) {
    const cv::Vec3b c = *it;
    if (std::max({c[0], c[1], c[2]}) - std::min({c[0], c[1], c[2]}) > 80) ++coloured;
  }
  EXPECT_GT(coloured, 1000);
}

TEST(EvalCli, NoOverlapFailsWithAMessageNamingBothFiles) {
  const std::string dir = test::scratchDir("eval");
  Trajectory gt, est;
  for (int k = 0; k < 10; ++k) {
    gt.push_back({(100 + k) * kNsPerSecond, SE3()});
    est.push_back({(200 + k) * kNsPerSecond, SE3()});
  }
  writeTumTrajectory(dir + "/the_gt.txt", gt);
  writeTumTrajectory(dir + "/the_est.txt", est);
  const CliRun r = run("--gt " + quoted(dir + "/the_gt.txt") + " --est " + quoted(dir + "/the_est.txt") + " --json 2>&1");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("the_gt.txt"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the_est.txt"), std::string::npos) << r.out;
}

TEST(EvalCli, BadOptionValuesAreRefused) {
  const CliRun r = run("--gt a.txt --est b.txt --delta -1 2>&1");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("--delta"), std::string::npos) << r.out;
  const CliRun missing = run("--gt a.txt 2>&1");
  EXPECT_EQ(missing.status, 2) << missing.out;
  EXPECT_NE(missing.out.find("--est"), std::string::npos) << missing.out;
  // eval loops refuses a tolerance it could not meet before reading any frame.
  const CliRun tolerance = run("loops --dataset /nonexistent --out /tmp/x --pose-tolerance-m -1 2>&1");
  EXPECT_EQ(tolerance.status, 2) << tolerance.out;
  EXPECT_NE(tolerance.out.find("--pose-tolerance-m"), std::string::npos) << tolerance.out;
}

TEST(EvalCli, LoopsOnTheSyntheticLapFindTheRevisitWithPrecisionOneAtTheOperatingThreshold) {
  // A short lap (150 frames at 320 x 240), every second frame: the curves, the plot and the
  // operating point after geometric verification, which is what a run would accept.
  const std::string scratch = test::scratchDir("evalloops");
  const std::string data = scratch + "/lap";
  const auto synth = test::runPlslam("synth --scene loop --frames 150 --width 320 --height 240 --out " + data);
  ASSERT_EQ(synth.status, 0) << synth.output;
  const CliRun r = run("loops --dataset " + data + " --out " + scratch + "/pr --every 2 --segmenter replay");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string json = test::readFile(scratch + "/pr/summary.json");
  const size_t verified = json.find("\"verified_at_threshold\"");
  ASSERT_NE(verified, std::string::npos) << json;
  EXPECT_GT(jsonNumber(json, "queries_with_true_loop"), 0) << json;
  EXPECT_DOUBLE_EQ(jsonNumber(json, "precision", verified), 1.0) << "a false loop passed verification:\n" << json;
  EXPECT_GT(jsonNumber(json, "recall", verified), 0.3) << json;
  EXPECT_GE(jsonNumber(json, "semantic_min_precision_margin"), 0.0) << json;
  EXPECT_FALSE(cv::imread(scratch + "/pr/pr.png").empty());
  const std::string csv = test::readFile(scratch + "/pr/pr.csv");
  for (const char* variant : {"\nORB,", "\nLBD,", "\nORB+LBD,", "\nORB+LBD+semantic,"})
    EXPECT_NE(csv.find(variant), std::string::npos) << variant;
}
