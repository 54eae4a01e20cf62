#include <gtest/gtest.h>

#include "core/error.h"
#include "core/map_frame.h"

using namespace plslam;

TEST(MapFrameYaml, RoundTripsAndSaysHowItWasFound) {
  MapFrame f;
  f.T_map_world = SE3(Eigen::Quaterniond(Eigen::AngleAxisd(-1.9, Eigen::Vector3d(0.3, 1, -0.2).normalized())),
                      Eigen::Vector3d(0.1, -0.2, 1.25));
  f.floor_method = "ransac";
  f.floor_source = "dense";
  f.floor_points = 1234;
  const std::string yaml = mapFrameToYaml(f);
  EXPECT_NE(yaml.find("camera_height_m: 1.25\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("parent_frame: map\nchild_frame: world\n"), std::string::npos);
  const MapFrame b = parseMapFrameYaml(yaml, "test");
  EXPECT_LT((b.T_map_world.inverse() * f.T_map_world).angle(), 1e-8);
  EXPECT_LT((b.T_map_world.translation() - f.T_map_world.translation()).norm(), 1e-8);
  EXPECT_EQ(b.floor_method, "ransac");
  EXPECT_EQ(b.floor_source, "dense");
  EXPECT_EQ(b.floor_points, 1234);
}

TEST(MapFrameYaml, RefusesMalformedFilesNamingTheKey) {
  const std::string good = mapFrameToYaml(MapFrame());
  const auto refuses = [](const std::string& text, const std::string& what) {
    try {
      parseMapFrameYaml(text, "f.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refuses("translation: [0, 0, 0]\n", "not a map frame file");
  std::string t = good;
  refuses(t.replace(t.find("translation: "), 13, "translate: "), "'translation' is missing");
  t = good;
  refuses(t.replace(t.find("rotation: ["), 11, "rotation: [2, "), "'rotation' needs 4 numbers");
  t = good;
  refuses(t.replace(t.find("rotation: [0"), 12, "rotation: [0.5"), "not a unit quaternion");
  t = good;
  refuses(t.replace(t.find("translation: [0"), 15, "translation: [x"), "bad number");
}
