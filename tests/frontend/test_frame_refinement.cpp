// Re-estimating a tracked frame against settled landmarks (frame_refinement.h): exact
// observations of exact landmarks give back the true pose from a wrong start; landmarks
// culled meanwhile are left out; mismatched match lists are refused.
#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "frontend/frame_refinement.h"
#include "synth/scene.h"

namespace plslam {
namespace {

// A map of `n` points 1-4 m in front of the camera at `T_w_c`, and the frame's exact
// observation of each (keypoint i matched to point i).
struct Scene {
  Map map;
  FrameFeatures features;
  std::vector<Id> point_ids;
};

Scene makeScene(const PinholeCamera& camera, const SE3& T_w_c, int n) {
  Scene s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(20, 620), v(20, 460), z(1, 4);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d uv(u(rng), v(rng));
    const double depth = z(rng);
    MapPoint p;
    p.p_w = T_w_c * camera.unprojectIdeal(uv, depth);
    s.point_ids.push_back(s.map.addPoint(std::move(p)));
    Keypoint k;
    k.uv = k.uv_raw = uv;
    k.depth_m = depth;
    s.features.points.push_back(k);
  }
  return s;
}

const SE3 kTruth(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
                 Eigen::Vector3d(0.5, -0.2, 1.0));

SE3 perturbed(const SE3& T) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.02, -0.015, 0.01, 0.01, -0.008, 0.012;  // 2.7 cm, about 0.9 degrees
  return T * SE3::exp(xi);
}

TEST(FrameRefinement, SettledLandmarksGiveBackTheTruePoseFromAWrongStart) {
  const PinholeCamera camera = synth::syntheticCamera(640, 480);
  Scene s = makeScene(camera, kTruth, 80);
  FrameObservations obs = matchedObservations(s.features, s.point_ids, {});
  ASSERT_EQ(obs.point_ids.size(), 80u);
  const PoseOnlyProblem problem = poseProblem(s.map, &obs, perturbed(kTruth));
  ASSERT_EQ(problem.points.size(), 80u);
  const auto T = solveRefinement(camera, PoseOptimizer(), problem, 20);
  ASSERT_TRUE(T.has_value());
  const SE3 err = kTruth.inverse() * *T;
  EXPECT_LT(err.translation().norm(), 1e-6);
  EXPECT_LT(err.angle(), 1e-6);
}

TEST(FrameRefinement, UnmatchedKeypointsAndCulledLandmarksAreLeftOut) {
  const PinholeCamera camera = synth::syntheticCamera(640, 480);
  Scene s = makeScene(camera, kTruth, 40);
  std::vector<Id> matches = s.point_ids;
  for (size_t i = 0; i < matches.size(); i += 4) matches[i] = kNoId;  // 10 keypoints not matched
  FrameObservations obs = matchedObservations(s.features, matches, {});
  EXPECT_EQ(obs.point_ids.size(), 30u);
  for (size_t i = 1; i < 20; i += 2) s.map.erasePoint(s.point_ids[i]);  // culled after tracking: 10 matched ones
  const PoseOnlyProblem problem = poseProblem(s.map, &obs, kTruth);
  EXPECT_EQ(problem.points.size(), 20u);
  // What stays lines up with the problem: the same keypoints and landmarks, in order.
  ASSERT_EQ(obs.point_ids.size(), 20u);
  for (size_t k = 0; k < obs.point_ids.size(); ++k) {
    EXPECT_EQ(obs.point_ids[k], s.point_ids[obs.point_index[k]]);
    EXPECT_EQ(problem.points[k].p_w, s.map.point(obs.point_ids[k])->p_w);
  }
  // Too few left: the frame keeps its tracked pose.
  EXPECT_FALSE(solveRefinement(camera, PoseOptimizer(), problem, 21).has_value());
  EXPECT_TRUE(solveRefinement(camera, PoseOptimizer(), problem, 20).has_value());
}

TEST(FrameRefinement, MatchListsOfTheWrongSizeAreRefused) {
  const PinholeCamera camera = synth::syntheticCamera(640, 480);
  Scene s = makeScene(camera, kTruth, 10);
  std::vector<Id> short_list(s.point_ids.begin(), s.point_ids.end() - 1);
  EXPECT_THROW(matchedObservations(s.features, short_list, {}), DataError);
  EXPECT_THROW(matchedObservations(s.features, s.point_ids, {kNoId}), DataError);
}

}  // namespace
}  // namespace plslam
