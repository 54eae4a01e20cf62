#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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
  const std::string json = statsToJson(s, "\"extra\": 1");
  for (const char* key : {"\"frames\": 10", "\"tracked\": 9", "\"keyframes\"", "\"lost_events\"", "\"tracking_ms\"",
                          "\"median\": 20", "\"p95\"", "\"features_ms\"", "\"line_reconstruction_rate\"", "\"fitting\"",
                          "\"endpoints\"", "\"extra\": 1", "\"stages_ms\"", "\"orb_detect\"", "\"lsd\"", "\"lbd\"",
                          "\"dynamic\"", "\"search\"", "\"pose_optimisation\"", "\"keyframe\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}
