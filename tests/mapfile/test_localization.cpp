// Localisation-only mode: a saved map, loaded, tracks a second pass of the scene without
// being changed, with poses in the map's world frame.
#include <gtest/gtest.h>

#include "eval/trajectory_eval.h"
#include "io/dataset.h"
#include "map_fixture.h"
#include "mapfile/map_file.h"
#include "system/system.h"

using namespace plslam;

namespace {

struct PassResult {
  Trajectory trajectory;
  RunStats stats;
  double ate = 0;
  std::string map_after;  ///< the map serialized after the pass
};

/// Feeds frames [first, last) of the synthetic sequence to a System on the saved map.
PassResult secondPass(bool localization_only, int first, int last, std::string* map_before) {
  const test::BuiltMap& b = test::builtMap();
  LoadedMap l = parseMap(serializeMap(*b.map, b.camera, b.config_yaml), "synthetic map");
  *map_before = serializeMap(l.map, l.camera, l.config_yaml);
  SystemOptions o;
  o.sequential = true;
  o.tracker.localization_only = localization_only;
  System slam(l.camera, o, std::move(l.map));
  slam.start();
  DatasetOptions dopt;
  dopt.max_frames = last;
  TumDataset data = TumDataset::open(b.dataset, b.camera, dopt);
  RgbdFrame frame;
  for (int i = 0; data.next(&frame); ++i)
    if (i >= first) slam.feed(frame);
  slam.finish();
  PassResult r;
  r.trajectory = slam.trajectory();
  r.stats = slam.stats();
  r.ate = evaluate(data.groundtruth(), r.trajectory).ate.stats.rmse;
  r.map_after = serializeMap(slam.map(), l.camera, l.config_yaml);
  return r;
}

}  // namespace

TEST(Localization, SecondPassTracksEveryFrameWithoutChangingTheMap) {
  const test::BuiltMap& b = test::builtMap();
  std::string before;
  const PassResult r = secondPass(true, 0, test::kMapFrames, &before);
  EXPECT_EQ(r.stats.frames, test::kMapFrames);
  EXPECT_EQ(r.stats.tracked, r.stats.frames) << "every frame of the second pass tracked";
  EXPECT_EQ(r.stats.keyframes, static_cast<int>(b.map->keyframes().size())) << "no new keyframes";
  EXPECT_TRUE(r.map_after == before) << "the map changed during localisation";
  std::printf("mapping run ATE %.5f m, localisation run ATE %.5f m (ratio %.2f)\n", b.ate, r.ate, r.ate / b.ate);
  EXPECT_LE(r.ate, 1.2 * b.ate);
  // Poses are in the map's world frame: frame by frame next to the mapping run's, without
  // any alignment.
  ASSERT_EQ(r.trajectory.size(), b.trajectory.size());
  for (size_t i = 0; i < r.trajectory.size(); ++i) {
    EXPECT_EQ(r.trajectory[i].t_ns, b.trajectory[i].t_ns);
    EXPECT_LT((r.trajectory[i].T_w_c.translation() - b.trajectory[i].T_w_c.translation()).norm(), 0.02) << "frame " << i;
  }
}

TEST(Localization, StartsAnywhereInTheMapBySearchingAllKeyframes) {
  std::string before;
  const int first = test::kMapFrames / 2;
  const PassResult r = secondPass(true, first, test::kMapFrames, &before);
  EXPECT_EQ(r.stats.frames, test::kMapFrames - first);
  EXPECT_EQ(r.stats.tracked, r.stats.frames);
  EXPECT_TRUE(r.map_after == before);
}

TEST(Localization, EmptyMapCannotBeLocalisedIn) {
  const test::BuiltMap& b = test::builtMap();
  SystemOptions o;
  o.sequential = true;
  o.tracker.localization_only = true;
  System slam(b.camera, o, Map());
  DatasetOptions dopt;
  dopt.max_frames = 3;
  TumDataset data = TumDataset::open(b.dataset, b.camera, dopt);
  RgbdFrame frame;
  while (data.next(&frame)) {
    const TrackingResult t = slam.feed(frame);
    EXPECT_EQ(t.status, TrackingStatus::kNotInitialized);
    EXPECT_NE(t.reason.find("map is empty"), std::string::npos) << t.reason;
  }
  slam.finish();
  EXPECT_TRUE(slam.map().keyframes().empty());
}

TEST(Localization, WithoutLocalizeOnlyALoadedMapIsExtended) {
  const test::BuiltMap& b = test::builtMap();
  std::string before;
  const PassResult r = secondPass(false, 0, 30, &before);
  EXPECT_EQ(r.stats.tracked, r.stats.frames);
  EXPECT_GT(r.stats.keyframes, static_cast<int>(b.map->keyframes().size())) << "mapping goes on in the loaded map";
  EXPECT_FALSE(r.map_after == before);
}

TEST(Localization, MappingOnALoadedMapIndexesItsKeyframesForLoopClosure) {
  // Mapping (not localisation-only) on a loaded map: a later pass can close loops with the
  // places of the first one, so they are in the loop closer's database from the start.
  const test::BuiltMap& b = test::builtMap();
  LoadedMap l = parseMap(serializeMap(*b.map, b.camera, b.config_yaml), "synthetic map");
  const size_t keyframes = l.map.keyframes().size();
  ASSERT_GT(keyframes, 1u);
  SystemOptions o;
  o.sequential = true;
  System slam(l.camera, o, std::move(l.map));
  ASSERT_NE(slam.loopCloser(), nullptr);
  EXPECT_EQ(slam.loopCloser()->indexedKeyframes(), keyframes);
}
