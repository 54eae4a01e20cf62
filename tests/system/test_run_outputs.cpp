#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "support/test_support.h"
#include "system/run_outputs.h"

using namespace plslam;

TEST(RunOutputs, SummaryStatistics) {
  const Summary s = summarize({5, 1, 3, 2, 4, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 9});
  EXPECT_DOUBLE_EQ(s.median, 3);
  EXPECT_NEAR(s.mean, 69.0 / 21, 1e-12);
  EXPECT_DOUBLE_EQ(s.p95, 5);
  EXPECT_DOUBLE_EQ(s.max, 9);
  EXPECT_DOUBLE_EQ(summarize({1, 2}).median, 1.5);
  EXPECT_DOUBLE_EQ(summarize({}).median, 0);
}

TEST(RunOutputs, SparseMapPlyListsPointsLinesAndEdges) {
  Map map;
  MapPoint p;
  p.p_w = {1, 2, 3};
  map.addPoint(p);
  MapLine l;
  l.P_w = {0, 0, 1};
  l.Q_w = {1, 0, 1};
  map.addLine(l);
  const std::string ply = sparseMapToPly(map);
  EXPECT_NE(ply.find("element vertex 3\n"), std::string::npos);
  EXPECT_NE(ply.find("element edge 1\n"), std::string::npos);
  std::istringstream is(ply.substr(ply.find("end_header\n") + 11));
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(is, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].rfind("1.00000 2.00000 3.00000", 0), 0u);
  EXPECT_EQ(rows[3], "1 2");
}

TEST(RunOutputs, StatsJsonHasTheDocumentedFields) {
  RunStats s;
  s.frames = 10;
  s.tracked = 9;
  s.tracking_ms = {10, 20, 30};
  const nlohmann::json j = test::parseJson(statsToJson(s, {{"extra", 1}, {"dataset", "a \"quoted\" \\ path"}}), "stats.json");
  EXPECT_EQ(j.at("frames"), 10);
  EXPECT_EQ(j.at("tracked"), 9);
  EXPECT_DOUBLE_EQ(j.at("tracked_fraction").get<double>(), 0.9);
  EXPECT_EQ(j.at("tracking_ms").at("median"), 20);
  EXPECT_EQ(j.at("extra"), 1);
  EXPECT_EQ(j.at("dataset"), "a \"quoted\" \\ path");
  for (const char* key : {"keyframes", "lost_events", "features_ms", "line_reconstruction_rate", "stages_ms", "dynamic",
                          "modules", "recovery", "tracking_methods"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j.at("tracking_ms").contains("p95"));
  EXPECT_TRUE(j.at("line_reconstruction_rate").contains("fitting"));
  EXPECT_TRUE(j.at("line_reconstruction_rate").contains("endpoints"));
  for (const char* stage : {"orb_detect", "lsd", "lbd", "dynamic", "search", "pose_optimisation", "keyframe"})
    EXPECT_TRUE(j.at("stages_ms").contains(stage)) << stage;
  // Members that are not an object are a programming error, not a silent string.
  EXPECT_THROW(statsToJson(s, std::string("\"extra\": 1")), std::invalid_argument);
}
