#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "features/line_extractor.h"
#include "features/matching.h"
#include "features/orb_extractor.h"
#include "synthetic_images.h"

namespace plslam {
namespace {

using Eigen::Vector2d;

struct Points {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  std::vector<Vector2d> uv;
  std::vector<int> octaves;
  std::vector<float> angles;
};

Points orb(const cv::Mat& img, const OrbOptions& o = {}) {
  Points p;
  extractOrb(img, cv::Mat(), o, &p.kps, &p.desc);
  for (const cv::KeyPoint& k : p.kps) {
    p.uv.emplace_back(k.pt.x, k.pt.y);
    p.octaves.push_back(k.octave);
    p.angles.push_back(k.angle);
  }
  return p;
}

TEST(Matching, HammingDistance) {
  uint8_t a[32] = {}, b[32] = {};
  EXPECT_EQ(hammingDistance(a, b), 0);
  b[0] = 0x01;
  b[31] = 0xff;
  b[13] = 0x81;
  EXPECT_EQ(hammingDistance(a, b), 11);
  cv::Mat r1(50, 32, CV_8U), r2(50, 32, CV_8U);
  cv::RNG rng(5);
  rng.fill(r1, cv::RNG::UNIFORM, 0, 256);
  rng.fill(r2, cv::RNG::UNIFORM, 0, 256);
  for (int i = 0; i < 50; ++i)
    EXPECT_EQ(hammingDistance(r1.ptr<uint8_t>(i), r2.ptr<uint8_t>(i)), cv::norm(r1.row(i), r2.row(i), cv::NORM_HAMMING));
}

TEST(Matching, BruteForceRecoversAnImageShift) {
  const cv::Mat big = test::blobImage({700, 540}, 51);
  const int dx = 13, dy = -9;
  const auto [img1, img2] = test::shiftedPair(big, {640, 480}, dx, dy);
  const Points a = orb(img1), b = orb(img2);
  const std::vector<float> scales = orbLevelScales(OrbOptions());
  const std::vector<DescriptorMatch> m = matchBruteForce(a.desc, b.desc, BruteForceOptions());
  ASSERT_GT(m.size(), 300u);
  int good = 0;
  std::vector<char> train_used(b.kps.size(), 0);
  for (const DescriptorMatch& x : m) {
    ASSERT_FALSE(train_used[size_t(x.train)]) << "each train row at most once";
    train_used[size_t(x.train)] = 1;
    EXPECT_EQ(x.distance, hammingDistance(a.desc.ptr<uint8_t>(x.query), b.desc.ptr<uint8_t>(x.train)));
    const Vector2d expected = a.uv[size_t(x.query)] - Vector2d(dx, dy);
    good += (b.uv[size_t(x.train)] - expected).norm() <= 2.0 * scales[size_t(a.octaves[size_t(x.query)])];
  }
  EXPECT_GT(good, 0.9 * m.size()) << good << " of " << m.size();
  // Rotation consistency keeps nearly all of them (no rotation here).
  const std::vector<DescriptorMatch> f = filterByOrientation(m, a.angles, b.angles);
  EXPECT_GT(f.size(), 0.9 * m.size());
}

TEST(Matching, RatioAndMutualRejectAmbiguity) {
  cv::Mat q(2, 32, CV_8U), t(3, 32, CV_8U);
  cv::RNG rng(7);
  rng.fill(q, cv::RNG::UNIFORM, 0, 256);
  rng.fill(t, cv::RNG::UNIFORM, 0, 256);
  // Train rows 1 and 2 are both copies of query 0: ambiguous for the ratio test.
  q.row(0).copyTo(t.row(1));
  q.row(0).copyTo(t.row(2));
  BruteForceOptions o;
  o.max_distance = 256;
  o.ratio = 0.8f;
  EXPECT_TRUE(matchBruteForce(q.row(0).clone(), t, o).empty());
  o.ratio = 1.0f;
  const auto m = matchBruteForce(q.row(0).clone(), t, o);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].train, 1) << "ties go to the lower index";
  EXPECT_EQ(m[0].distance, 0);

  // Two identical queries, one train: mutual keeps one, never both.
  cv::Mat qq(2, 32, CV_8U);
  q.row(1).copyTo(qq.row(0));
  q.row(1).copyTo(qq.row(1));
  BruteForceOptions mutual;
  mutual.max_distance = 256;
  mutual.ratio = 1.0f;
  const auto mm = matchBruteForce(qq, q.row(1).clone(), mutual);
  ASSERT_EQ(mm.size(), 1u);
  EXPECT_EQ(mm[0].query, 0);
  mutual.mutual = false;
  EXPECT_EQ(matchBruteForce(qq, q.row(1).clone(), mutual).size(), 1u) << "train rows are still used once";

  EXPECT_TRUE(matchBruteForce(cv::Mat(), t, o).empty());
  EXPECT_THROW(matchBruteForce(cv::Mat(2, 16, CV_8U, cv::Scalar(0)), t, o), DataError);
  EXPECT_THROW(matchBruteForce(cv::Mat(2, 32, CV_32F, cv::Scalar(0)), t, o), DataError);
}

TEST(Matching, OrientationFilterKeepsTheDominantRotation) {
  std::vector<DescriptorMatch> m;
  std::vector<float> qa, ta;
  cv::RNG rng(9);
  for (int i = 0; i < 200; ++i) {
    const float a = float(rng.uniform(0.0, 360.0));
    qa.push_back(a);
    const bool outlier = i % 10 == 0;
    const float rot = outlier ? float(rng.uniform(100.0, 300.0)) : 30.0f + float(rng.uniform(-4.0, 4.0));
    ta.push_back(std::fmod(a + rot, 360.0f));
    m.push_back({i, i, 10});
  }
  const std::vector<DescriptorMatch> f = filterByOrientation(m, qa, ta);
  int inliers_kept = 0, outliers_kept = 0;
  for (const DescriptorMatch& x : f) (x.query % 10 == 0 ? outliers_kept : inliers_kept)++;
  EXPECT_EQ(inliers_kept, 180);
  EXPECT_LE(outliers_kept, 4);
  for (size_t i = 1; i < f.size(); ++i) EXPECT_LT(f[i - 1].query, f[i].query) << "input order kept";
  EXPECT_TRUE(filterByOrientation({}, qa, ta).empty());
  EXPECT_THROW(filterByOrientation({{500, 0, 0}}, qa, ta), DataError);
}

TEST(Matching, PointGridAgreesWithBruteForce) {
  cv::RNG rng(11);
  std::vector<Vector2d> pts;
  for (int i = 0; i < 800; ++i) pts.emplace_back(rng.uniform(-30.0, 670.0), rng.uniform(-30.0, 510.0));
  pts.emplace_back(NAN, 5.0);  // never returned
  const PointGrid grid(pts, 640, 480, 16);
  std::vector<int> got;
  for (int k = 0; k < 300; ++k) {
    const Vector2d c(rng.uniform(-60.0, 700.0), rng.uniform(-60.0, 540.0));
    const double r = rng.uniform(0.0, 40.0);
    grid.query(c, r, &got);
    std::sort(got.begin(), got.end());
    std::vector<int> want;
    for (size_t i = 0; i < pts.size(); ++i)
      if ((pts[i] - c).squaredNorm() <= r * r) want.push_back(int(i));
    ASSERT_EQ(got, want) << "centre " << c.transpose() << " radius " << r;
  }
  PointGrid empty;
  empty.query({1, 1}, 100, &got);
  EXPECT_TRUE(got.empty());
}

// The grid returns candidates cell by cell, not by index: an equally close look-alike in an
// earlier cell must not win over the lower index.
TEST(Matching, ProjectionTiesGoToTheLowerIndexWhicheverCellComesFirst) {
  cv::Mat descriptors(3, 32, CV_8U, cv::Scalar(0x5A));
  descriptors.row(2).setTo(0xA5);  // far from the query: only there to be an index
  // Keypoint 0 lies in a later row of cells than keypoint 1; both have the query's descriptor.
  const std::vector<Vector2d> uv = {{100, 140}, {130, 100}, {110, 110}};
  const PointGrid grid(uv, 640, 480, 16);
  std::vector<PointPrediction> pred = {{{110, 120}, -1}};
  const cv::Mat query(1, 32, CV_8U, cv::Scalar(0x5A));
  PointProjectionOptions o;
  o.radius_px = 40;
  o.ratio = 1.0f;  // a tie is not ambiguous here: the test is about which one wins
  const std::vector<DescriptorMatch> m = matchPointsByProjection(pred, query, grid, {}, descriptors, o);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].train, 0);
  EXPECT_EQ(m[0].distance, 0);
}

TEST(Matching, ProjectionWithExactPredictionsRecoversThePairs) {
  const cv::Mat big = test::blobImage({700, 540}, 53);
  const int dx = -7, dy = 12;
  const auto [img1, img2] = test::shiftedPair(big, {640, 480}, dx, dy);
  const Points a = orb(img1), b = orb(img2);
  const std::vector<float> scales = orbLevelScales(OrbOptions());
  std::vector<PointPrediction> pred;
  for (size_t i = 0; i < a.uv.size(); ++i) pred.push_back({a.uv[i] - Vector2d(dx, dy), a.octaves[i]});
  const PointGrid grid(b.uv, 640, 480);
  const std::vector<DescriptorMatch> m =
      matchPointsByProjection(pred, a.desc, grid, b.octaves, b.desc, PointProjectionOptions());
  // The pairs that exist: a keypoint of the same level at the predicted place.
  int exist = 0;
  std::vector<int> truth(pred.size(), -1);
  for (size_t i = 0; i < pred.size(); ++i)
    for (size_t j = 0; j < b.uv.size(); ++j)
      if (b.octaves[j] == pred[i].octave && (b.uv[j] - pred[i].uv).norm() <= 0.5 * scales[size_t(pred[i].octave)]) {
        truth[i] = int(j);
        ++exist;
        break;
      }
  ASSERT_GT(exist, 300);
  // Where the true keypoint exists it wins; elsewhere a nearby look-alike may be taken
  // (the distance threshold decides), which is what a tracker expects.
  int correct = 0, wrong = 0;
  for (const DescriptorMatch& x : m) {
    const size_t i = size_t(x.query);
    if (truth[i] < 0) continue;
    if (x.train == truth[i]) ++correct;
    else if ((b.uv[size_t(x.train)] - pred[i].uv).norm() > 2.0 * scales[size_t(pred[i].octave)]) ++wrong;
  }
  EXPECT_GT(correct, 0.9 * exist) << correct << " of " << exist;
  EXPECT_LT(wrong, 0.02 * exist) << wrong << " of " << exist;

  // Excluded keypoints are never returned.
  std::vector<char> excluded(b.uv.size(), 0);
  for (size_t j = 0; j < excluded.size(); j += 2) excluded[j] = 1;
  for (const DescriptorMatch& x : matchPointsByProjection(pred, a.desc, grid, b.octaves, b.desc, {}, excluded))
    EXPECT_EQ(x.train % 2, 1);
  // Predictions far from everything find nothing; malformed input is refused.
  std::vector<PointPrediction> far = {{Vector2d(-500, -500), 0}};
  EXPECT_TRUE(matchPointsByProjection(far, a.desc.row(0).clone(), grid, b.octaves, b.desc, {}).empty());
  EXPECT_THROW(matchPointsByProjection(far, a.desc, grid, b.octaves, b.desc, {}), DataError);
}

TEST(Matching, LinesByDescriptorAndByProjection) {
  const cv::Mat big = test::structureImage({720, 560}, 57);
  const int dx = 9, dy = 14;
  const auto [img1, img2] = test::shiftedPair(big, {640, 480}, dx, dy);
  const std::vector<LineSegment2D> la = detectLines(img1, cv::Mat(), LineOptions());
  const std::vector<LineSegment2D> lb = detectLines(img2, cv::Mat(), LineOptions());
  const cv::Mat da = describeLines(img1, la, LineOptions()), db = describeLines(img2, lb, LineOptions());
  ASSERT_GT(la.size(), 15u);
  const Vector2d shift(dx, dy);
  auto sameLine = [&](const LineSegment2D& s, const LineSegment2D& t) {  // s in image 1, t in image 2
    const Vector2d u = (s.q - s.p).normalized();
    const Vector2d m = 0.5 * (t.p + t.q) + shift - s.p;
    return u.dot((t.q - t.p).normalized()) > 0.99 && std::abs(m.x() * u.y() - m.y() * u.x()) < 1.5;
  };

  BruteForceOptions bo;
  bo.max_distance = 80;
  const std::vector<DescriptorMatch> m = matchBruteForce(da, db, bo);
  ASSERT_GT(m.size(), 10u);
  int good = 0;
  for (const DescriptorMatch& x : m) good += sameLine(la[size_t(x.query)], lb[size_t(x.train)]);
  EXPECT_GT(good, 0.9 * m.size()) << good << " of " << m.size();

  // By projection: image-1 segments moved by the known shift predict image 2.
  std::vector<LineSegment2D> pred;
  for (const LineSegment2D& s : la) pred.push_back(LineSegment2D::fromEndpoints(s.p - shift, s.q - shift));
  const std::vector<DescriptorMatch> pm = matchLinesByProjection(pred, da, lb, db, LineProjectionOptions());
  int exist = 0;
  for (const LineSegment2D& s : la)
    for (const LineSegment2D& t : lb)
      if (sameLine(s, t)) {
        ++exist;
        break;
      }
  int correct = 0;
  for (const DescriptorMatch& x : pm) correct += sameLine(la[size_t(x.query)], lb[size_t(x.train)]);
  EXPECT_EQ(correct, static_cast<int>(pm.size())) << "every projection match is right";
  EXPECT_GT(correct, 0.9 * exist) << correct << " of " << exist;
  // Geometric gates: rotated predictions find nothing.
  std::vector<LineSegment2D> rotated;
  for (const LineSegment2D& s : pred) {
    const Vector2d c = 0.5 * (s.p + s.q), h = 0.5 * (s.q - s.p);
    rotated.push_back(LineSegment2D::fromEndpoints(c - Vector2d(-h.y(), h.x()), c + Vector2d(-h.y(), h.x())));
  }
  EXPECT_TRUE(matchLinesByProjection(rotated, da, lb, db, LineProjectionOptions()).empty());
}

}  // namespace
}  // namespace plslam
