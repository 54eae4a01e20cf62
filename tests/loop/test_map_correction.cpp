// Applying a loop correction solved on a snapshot to a map that moved on meanwhile
// (loop/map_correction.h): keyframes added and poses and points refined by local BA while
// the loop thread was solving must keep what happened to them, moved by the correction.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "loop/map_correction.h"

using namespace plslam;

namespace {

SE3 pose(double x, double yaw_deg) {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY())),
             Eigen::Vector3d(x, 0, 0));
}

Id addKeyframe(Map* map, const SE3& T_w_c) {
  KeyFrame kf;
  kf.T_w_c = T_w_c;
  kf.features.points.resize(2);
  kf.point_ids.assign(2, kNoId);
  return map->addKeyFrame(std::move(kf));
}

Id addPoint(Map* map, Id kf, int index, const Eigen::Vector3d& p_w) {
  MapPoint p;
  p.p_w = p_w;
  p.first_keyframe = kf;
  const Id id = map->addPoint(std::move(p));
  map->addPointObservation(kf, index, id);
  return id;
}

void expectPoseNear(const SE3& a, const SE3& b) {
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-12);
  EXPECT_LT(a.quaternion().angularDistance(b.quaternion()), 1e-12);
}

}  // namespace

TEST(MapCorrection, KeyframesAddedSinceTheSnapshotMoveWithTheNewestSnapshotKeyframe) {
  Map map;
  const Id a = addKeyframe(&map, pose(0, 0)), b = addKeyframe(&map, pose(1, 10));
  const std::vector<Id> ids{a, b};
  const std::vector<SE3> snapshot{pose(0, 0), pose(1, 10)};
  const std::vector<SE3> solved{pose(0, 0), pose(0.9, 5)};
  const Id late = addKeyframe(&map, pose(1.2, 12));  // tracked while the solver ran

  const std::map<Id, SE3> change = keyframeChanges(map, ids, snapshot, solved);
  ASSERT_EQ(change.size(), 3u);
  expectPoseNear(change.at(a), SE3());
  expectPoseNear(change.at(b), solved[1] * snapshot[1].inverse());
  expectPoseNear(change.at(late), change.at(b));

  applyChanges(&map, change, {});
  expectPoseNear(map.keyframe(b)->T_w_c, solved[1]);
  // The late keyframe keeps its pose relative to b.
  expectPoseNear(map.keyframe(b)->T_w_c.inverse() * map.keyframe(late)->T_w_c, pose(1, 10).inverse() * pose(1.2, 12));
}

TEST(MapCorrection, LocalBundleAdjustmentSinceTheSnapshotIsKeptUnderTheCorrection) {
  Map map;
  const Id a = addKeyframe(&map, pose(0, 0)), b = addKeyframe(&map, pose(1, 10));
  const std::vector<SE3> snapshot{pose(0, 0), pose(1, 10)}, solved{pose(0, 0), pose(0.8, 4)};
  const Id still = addPoint(&map, b, 0, Eigen::Vector3d(1, 0, 2));
  const Id moved = addPoint(&map, b, 1, Eigen::Vector3d(1, 1, 2));
  const std::map<Id, std::pair<Eigen::Vector3d, Eigen::Vector3d>> solved_points{
      {still, {Eigen::Vector3d(1, 0, 2), Eigen::Vector3d(0.7, 0, 2.1)}},
      {moved, {Eigen::Vector3d(1, 1, 2), Eigen::Vector3d(0.7, 1, 2.1)}}};
  // Local BA refined b and one point while the loop was solved.
  const SE3 refined_b = pose(1.01, 10.5);
  map.keyframe(b)->T_w_c = refined_b;
  map.point(moved)->p_w = Eigen::Vector3d(1.02, 1, 2);

  const std::map<Id, SE3> change = keyframeChanges(map, {a, b}, snapshot, solved);
  const uint64_t before = map.corrections();
  applyChanges(&map, change, solved_points);

  expectPoseNear(map.keyframe(b)->T_w_c, change.at(b) * refined_b);
  EXPECT_LT((map.point(still)->p_w - Eigen::Vector3d(0.7, 0, 2.1)).norm(), 1e-12) << "unchanged since: solved position";
  EXPECT_LT((map.point(moved)->p_w - change.at(b) * Eigen::Vector3d(1.02, 1, 2)).norm(), 1e-12)
      << "moved since: its refined position, carried by its keyframe's correction";
  EXPECT_EQ(map.corrections(), before + 1);
}

TEST(MapCorrection, LinesFollowTheirFirstKeyframe) {
  Map map;
  const Id a = addKeyframe(&map, pose(0, 0)), b = addKeyframe(&map, pose(1, 10));
  MapLine l;
  l.P_w = Eigen::Vector3d(0, 0, 3);
  l.Q_w = Eigen::Vector3d(1, 0, 3);
  l.first_keyframe = b;
  const Id line = map.addLine(std::move(l));
  const std::vector<SE3> snapshot{pose(0, 0), pose(1, 10)}, solved{pose(0, 0), pose(0.5, 0)};
  const std::map<Id, SE3> change = keyframeChanges(map, {a, b}, snapshot, solved);
  applyChanges(&map, change, {});
  EXPECT_LT((map.line(line)->P_w - change.at(b) * Eigen::Vector3d(0, 0, 3)).norm(), 1e-12);
  EXPECT_LT((map.line(line)->Q_w - change.at(b) * Eigen::Vector3d(1, 0, 3)).norm(), 1e-12);
}
