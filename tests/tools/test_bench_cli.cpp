// Runs the built `plslam bench` as a user would, on a short synthetic scene with no shared/.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/test_support.h"

using namespace plslam;

namespace {

struct CliRun {
  int status = -1;  ///< exit code
  std::string out;  ///< stdout and stderr
};

CliRun run(const std::string& args) {
  const test::CommandResult r = test::runPlslam("bench " + args, true);
  return {r.status, r.output};
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The cells of the Markdown table row whose first cell is `name` (empty when none).
std::vector<std::string> tableRow(const std::string& md, const std::string& name) {
  std::istringstream in(md);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| " + name + " |", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    for (std::string c; std::getline(ss, c, '|');) {
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      cells.push_back(c);
    }
    return cells;
  }
  return {};
}

}  // namespace

TEST(BenchCli, SyntheticSceneGivesATableRowAndJsonAndAnnouncesTheTumSkip) {
  const std::string out = test::scratchDir("bench");
  const CliRun r = run("--runs 1 --scenes static --synthetic-frames 40 --shared /nonexistent --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.out;

  // The missing shared/ folder is said, not silently ignored.
  EXPECT_NE(r.out.find("TUM sequences skipped"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("/nonexistent"), std::string::npos) << r.out;

  const std::string md = readFile(out + "/results.md");
  const std::vector<std::string> row = tableRow(md, "synthetic_static");
  ASSERT_GE(row.size(), 11u) << md;
  EXPECT_EQ(std::atoi(row[1].c_str()), 40) << "frames column";
  const double ate = std::strtod(row[2].c_str(), nullptr);
  EXPECT_TRUE(std::isfinite(ate) && ate >= 0) << "ATE cell: " << row[2];
  EXPECT_EQ(row[8], "yes") << "lines column";
  EXPECT_EQ(row[9], "geometry") << "dynamic column";
  EXPECT_EQ(row[10], "yes") << "loop column (on by default)";
  // The same table went to stdout.
  EXPECT_NE(r.out.find("| synthetic_static | 40 |"), std::string::npos);

  const nlohmann::json json = test::readJson(out + "/results.json");
  ASSERT_TRUE(json.is_object());
  EXPECT_TRUE(json.at("peak_rss_mb").is_number());
  ASSERT_EQ(json.at("sequences").size(), 1u) << json;
  const nlohmann::json& seq = json.at("sequences")[0];
  EXPECT_EQ(seq.at("sequence"), "synthetic_static");
  EXPECT_EQ(seq.at("frames"), 40);
  EXPECT_NEAR(seq.at("ate_rmse").at("median").get<double>(), ate, 1e-4) << "the table's ATE";
  EXPECT_EQ(seq.at("runs").size(), 1u);

  // Each run's outputs and the plot of the median run.
  namespace fs = std::filesystem;
  EXPECT_TRUE(fs::exists(out + "/synthetic_static/run1/trajectory.txt"));
  EXPECT_TRUE(fs::exists(out + "/synthetic_static/run1/stats.json"));
  EXPECT_TRUE(fs::exists(out + "/synthetic_static/trajectory.png"));
}

TEST(BenchCli, UnknownSceneIsRefused) {
  const std::string out = test::scratchDir("bench");
  const CliRun r = run("--runs 1 --scenes nosuchscene --shared /nonexistent --out '" + out + "'");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("nosuchscene"), std::string::npos) << r.out;
}

TEST(BenchCli, MasksReplayTheSyntheticScenesMasksAndSayItInTheTable) {
  const std::string out = test::scratchDir("bench");
  const CliRun r = run("--runs 1 --scenes dynamic --synthetic-frames 30 --masks --shared /nonexistent --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::vector<std::string> row = tableRow(readFile(out + "/results.md"), "synthetic_dynamic");
  ASSERT_GE(row.size(), 11u);
  EXPECT_EQ(row[9], "replayed masks") << "dynamic column";
  // The run really had the replay segmenter, not geometry only.
  const nlohmann::json stats = test::readJson(out + "/synthetic_dynamic/run1/stats.json");
  EXPECT_EQ(stats.at("dynamic").at("segmenter"), "replay") << stats;
}

TEST(BenchCli, TakesTheSegmenterFromTheConfigurationAsRunDoes) {
  const std::string out = test::scratchDir("bench");
  const std::string cfg = out + "/replay.yaml";
  std::ofstream(cfg) << "segmenter:\n  backend: replay\n";
  const CliRun r = run("--runs 1 --scenes dynamic --synthetic-frames 30 --config '" + cfg + "' --shared /nonexistent --out '" +
                       out + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::vector<std::string> row = tableRow(readFile(out + "/results.md"), "synthetic_dynamic");
  ASSERT_GE(row.size(), 11u);
  EXPECT_EQ(row[9], "replayed masks") << "dynamic column";
  const nlohmann::json stats = test::readJson(out + "/synthetic_dynamic/run1/stats.json");
  EXPECT_EQ(stats.at("dynamic").at("segmenter"), "replay") << stats;

  std::ofstream(cfg) << "segmenter:\n  backend: maskrcnn\n";
  const CliRun bad = run("--runs 1 --scenes none --config '" + cfg + "' --shared /nonexistent --out '" + out + "/bad'");
  EXPECT_NE(bad.status, 0) << bad.out;
  EXPECT_NE(bad.out.find("segmenter.backend"), std::string::npos) << bad.out;
}

TEST(BenchCli, MasksWithoutAModelForTheTumRowsAreRefusedBeforeAnyRun) {
  namespace fs = std::filesystem;
  const std::string out = test::scratchDir("bench");
  // A shared/ folder with one TUM-looking sequence and no model.
  const std::string shared = test::scratchDir("bench_shared");
  fs::create_directories(shared + "/data/tum/fr1_tiny");
  std::ofstream(shared + "/data/tum/fr1_tiny/rgb.txt") << "# empty\n";
  const CliRun r = run("--runs 1 --scenes none --masks --shared '" + shared + "' --out '" + out + "'");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("yolov8n-seg-320.onnx"), std::string::npos) << "the missing model is named: " << r.out;
  EXPECT_FALSE(fs::exists(out + "/results.md")) << "nothing was run";
}

// Each seed is a rendering of its own (its row, its folder, its scene.txt), and the report
// sums the seeds up; a seed list that says nothing is refused before any rendering.
TEST(BenchCli, SyntheticSeedsGiveOneRowEachAndASummaryLine) {
  const std::string out = test::scratchDir("bench_seeds");
  const CliRun r = run("--runs 1 --sequential --scenes static --synthetic-frames 30 --synthetic-seeds 1-2 "
                       "--shared /nonexistent --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string md = readFile(out + "/results.md");
  ASSERT_GE(tableRow(md, "synthetic_static_seed1").size(), 11u) << md;
  ASSERT_GE(tableRow(md, "synthetic_static_seed2").size(), 11u) << md;
  EXPECT_TRUE(tableRow(md, "synthetic_static").empty()) << md;
  const std::string scene1 = readFile(out + "/synthetic_static_seed1/scene.txt");
  const std::string scene2 = readFile(out + "/synthetic_static_seed2/scene.txt");
  EXPECT_NE(scene1.find("seed 1"), std::string::npos) << scene1;
  EXPECT_NE(scene2.find("seed 2"), std::string::npos) << scene2;
  EXPECT_NE(md.find("- synthetic static over 2 seeds: ATE median "), std::string::npos) << md;

  for (const char* bad : {"0", "3-1", "x", "1-"}) {
    const CliRun refused = run(std::string("--runs 1 --scenes static --synthetic-seeds ") + bad +
                               " --shared /nonexistent --out '" + out + "/bad'");
    EXPECT_NE(refused.status, 0) << bad;
    EXPECT_NE(refused.out.find("--synthetic-seeds"), std::string::npos) << refused.out;
    EXPECT_FALSE(std::filesystem::exists(out + "/bad/synthetic_static_seed1")) << bad;
  }
}
