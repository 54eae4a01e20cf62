#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <thread>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "features/orb_extractor.h"
#include "synthetic_images.h"

namespace plslam {
namespace {

struct Orb {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
};

Orb run(const cv::Mat& img, const cv::Mat& mask = cv::Mat(), const OrbOptions& o = {}) {
  Orb r;
  extractOrb(img, mask, o, &r.kps, &r.desc);
  return r;
}

void expectWellFormed(const Orb& r) {
  EXPECT_EQ(r.desc.rows, static_cast<int>(r.kps.size()));
  EXPECT_EQ(r.desc.cols, 32);
  EXPECT_EQ(r.desc.type(), CV_8U);
}

void expectSame(const Orb& a, const Orb& b) {
  ASSERT_EQ(a.kps.size(), b.kps.size());
  for (size_t i = 0; i < a.kps.size(); ++i) {
    EXPECT_EQ(a.kps[i].pt, b.kps[i].pt);
    EXPECT_EQ(a.kps[i].angle, b.kps[i].angle);
    EXPECT_EQ(a.kps[i].octave, b.kps[i].octave);
    EXPECT_EQ(a.kps[i].response, b.kps[i].response);
  }
  EXPECT_EQ(cv::norm(a.desc, b.desc, cv::NORM_HAMMING), 0.0);
}

TEST(Orb, KeypointsOnlyWhereTextureIs) {
  cv::Mat img(480, 640, CV_8U, cv::Scalar(128));
  const cv::Rect tex(200, 120, 240, 200);
  test::blobImage(tex.size(), 1).copyTo(img(tex));
  const Orb r = run(img);
  expectWellFormed(r);
  ASSERT_GT(r.kps.size(), 200u);
  const std::vector<float> scales = orbLevelScales(OrbOptions());
  for (const cv::KeyPoint& k : r.kps) {
    // A FAST corner sits within its 3-pixel circle of the texture, in level pixels.
    const float margin = 4.0f * scales[static_cast<size_t>(k.octave)];
    EXPECT_GE(k.pt.x, tex.x - margin);
    EXPECT_LE(k.pt.x, tex.x + tex.width + margin);
    EXPECT_GE(k.pt.y, tex.y - margin);
    EXPECT_LE(k.pt.y, tex.y + tex.height + margin);
  }
}

TEST(Orb, TexturelessImageGivesNothing) {
  const cv::Mat flat(480, 640, CV_8U, cv::Scalar(90));
  Orb r = run(flat);
  expectWellFormed(r);
  EXPECT_TRUE(r.kps.empty());
  // A smooth ramp has gradient but no corner.
  cv::Mat ramp(480, 640, CV_8U);
  for (int y = 0; y < ramp.rows; ++y)
    for (int x = 0; x < ramp.cols; ++x) ramp.at<uint8_t>(y, x) = static_cast<uint8_t>(x * 255 / ramp.cols);
  r = run(ramp);
  expectWellFormed(r);
  EXPECT_TRUE(r.kps.empty());
}

TEST(Orb, EmptyAndTinyImagesGiveNothing) {
  for (const cv::Mat& img : {cv::Mat(), cv::Mat(cv::Mat::zeros(10, 10, CV_8U)), test::blobImage({10, 10}, 3, 5),
                             test::blobImage({32, 32}, 4, 10), cv::Mat(cv::Mat::zeros(1, 1000, CV_8U)),
                             cv::Mat(cv::Mat::zeros(480, 640, CV_8U))}) {
    const Orb r = run(img);
    expectWellFormed(r);
    EXPECT_TRUE(r.kps.empty()) << img.cols << "x" << img.rows;
  }
  // Just big enough for level 0: whatever it finds is well formed.
  expectWellFormed(run(test::blobImage({40, 40}, 5, 20)));
}

TEST(Orb, NoKeypointOnForbiddenPixels) {
  const cv::Mat img = test::blobImage({640, 480}, 7);
  cv::Mat mask(img.size(), CV_8U, cv::Scalar(255));
  cv::rectangle(mask, cv::Rect(100, 80, 220, 180), cv::Scalar(0), -1);
  cv::circle(mask, cv::Point(480, 330), 90, cv::Scalar(0), -1);
  OrbOptions o;
  const Orb r = run(img, mask, o);
  expectWellFormed(r);
  // The budget is filled from the allowed part.
  EXPECT_GE(static_cast<int>(r.kps.size()), o.num_features * 9 / 10);
  int near_border = 0;
  for (const cv::KeyPoint& k : r.kps) {
    const int x = static_cast<int>(std::lround(k.pt.x)), y = static_cast<int>(std::lround(k.pt.y));
    ASSERT_NE(mask.at<uint8_t>(y, x), 0) << "keypoint at " << k.pt << " octave " << k.octave;
    near_border += (x >= 95 && x < 325 && y >= 75 && y < 265);  // within 5 px of the rectangle
  }
  EXPECT_GT(near_border, 0) << "the mask should forbid its pixels, not a wide margin";

  const cv::Mat all_forbidden = cv::Mat::zeros(img.size(), CV_8U);
  const Orb none = run(img, all_forbidden);
  expectWellFormed(none);
  EXPECT_TRUE(none.kps.empty());
}

TEST(Orb, RespectsNumFeatures) {
  const cv::Mat img = test::blobImage({640, 480}, 11);
  for (int n : {0, 50, 300, 1000, 2000}) {
    OrbOptions o;
    o.num_features = n;
    const Orb r = run(img, cv::Mat(), o);
    expectWellFormed(r);
    EXPECT_LE(static_cast<int>(r.kps.size()), n);
    EXPECT_GE(static_cast<int>(r.kps.size()), n * 95 / 100) << n;
  }
}

TEST(Orb, SpreadsOverWeakTextureToo) {
  // Left half: strong texture; right half: the same kind of texture at 15% contrast. A
  // strongest-first selection would take nearly everything on the left.
  cv::Mat img = test::blobImage({640, 480}, 13);
  test::blobImage({320, 480}, 14, -1, 0.15).copyTo(img(cv::Rect(320, 0, 320, 480)));
  const Orb r = run(img);
  expectWellFormed(r);
  int right = 0;
  for (const cv::KeyPoint& k : r.kps) right += k.pt.x >= 320;
  EXPECT_GE(right, static_cast<int>(r.kps.size()) / 6) << right << " of " << r.kps.size();
  // cv::ORB's own selection (strongest Harris scores) as the baseline.
  std::vector<cv::KeyPoint> plain;
  cv::ORB::create(1000)->detect(img, plain);
  int plain_right = 0;
  for (const cv::KeyPoint& k : plain) plain_right += k.pt.x >= 320;
  EXPECT_GE(right, 2 * plain_right) << "cv::ORB: " << plain_right << " of " << plain.size();
  // And over the image: each of 4x4 blocks of the strong half holds keypoints.
  std::vector<int> blocks(8, 0);
  for (const cv::KeyPoint& k : r.kps)
    if (k.pt.x < 320) ++blocks[static_cast<size_t>(std::min(1, int(k.pt.x) / 160) * 4 + std::min(3, int(k.pt.y) / 120))];
  for (int b : blocks) EXPECT_GT(b, 10);
}

TEST(Orb, KeypointFieldsAreConsistent) {
  const cv::Mat img = test::blobImage({640, 480}, 17);
  OrbOptions o;
  const Orb r = run(img, cv::Mat(), o);
  expectWellFormed(r);
  const std::vector<float> scales = orbLevelScales(o);
  std::vector<int> per_level(static_cast<size_t>(o.num_levels), 0);
  int last_octave = 0;
  for (const cv::KeyPoint& k : r.kps) {
    ASSERT_GE(k.octave, 0);
    ASSERT_LT(k.octave, o.num_levels);
    EXPECT_GE(k.octave, last_octave) << "sorted by octave";
    last_octave = k.octave;
    ++per_level[static_cast<size_t>(k.octave)];
    const float s = scales[static_cast<size_t>(k.octave)];
    EXPECT_FLOAT_EQ(k.size, 31.0f * s);
    EXPECT_GE(k.angle, 0.0f);
    EXPECT_LT(k.angle, 360.0f);
    EXPECT_GT(k.response, 0.0f);
    EXPECT_GE(k.pt.x, kOrbEdge * s - 1e-3f);
    EXPECT_GE(k.pt.y, kOrbEdge * s - 1e-3f);
    EXPECT_LT(k.pt.x, img.cols - kOrbEdge * s + s);
    EXPECT_LT(k.pt.y, img.rows - kOrbEdge * s + s);
  }
  for (int n : per_level) EXPECT_GT(n, 0) << "every level contributes";
  EXPECT_GT(per_level[0], per_level[7]) << "finer levels get more";
}

TEST(Orb, AnglesFollowImageRotation) {
  const cv::Mat img = test::blobImage({480, 480}, 19);
  cv::Mat rot;
  cv::rotate(img, rot, cv::ROTATE_90_CLOCKWISE);  // (x, y) -> (H - 1 - y, x)
  const Orb a = run(img), b = run(rot);
  int paired = 0, good = 0;
  for (const cv::KeyPoint& ka : a.kps) {
    if (ka.octave != 0) continue;  // level 0 rotates pixel-exactly
    const cv::Point2f expected(img.rows - 1 - ka.pt.y, ka.pt.x);
    for (const cv::KeyPoint& kb : b.kps) {
      if (kb.octave != 0 || cv::norm(kb.pt - expected) > 0.5) continue;
      ++paired;
      const double diff = std::fmod(kb.angle - ka.angle + 720.0, 360.0);
      good += std::abs(diff - 90.0) < 2.0;
    }
  }
  ASSERT_GT(paired, 50);
  EXPECT_GE(good, paired * 95 / 100) << good << " of " << paired;
}

TEST(Orb, Deterministic) {
  const cv::Mat img = test::blobImage({640, 480}, 23);
  cv::Mat mask(img.size(), CV_8U, cv::Scalar(255));
  cv::circle(mask, {320, 240}, 80, cv::Scalar(0), -1);
  expectSame(run(img, mask), run(img.clone(), mask.clone()));
}

TEST(Orb, CoarseLevelsOnAnotherThreadGiveTheSameKeypoints) {
  // A weakly textured corner leaves some levels short of keypoints, so the carry from one
  // level to the next matters too.
  cv::Mat img = test::blobImage({640, 480}, 31);
  img(cv::Rect(0, 0, 320, 240)).setTo(128);
  cv::Mat mask(img.size(), CV_8U, cv::Scalar(255));
  cv::circle(mask, {420, 300}, 60, cv::Scalar(0), -1);
  const Orb whole = run(img, mask);
  ASSERT_GT(whole.kps.size(), 500u);

  OrbExtraction orb(img, mask, OrbOptions());
  ASSERT_EQ(orb.levels(), 8);
  const int split = orb.coarseLevelsStart();
  std::thread coarse([&] { orb.detectLevels(split, orb.levels()); });
  orb.detectLevels(0, split);
  coarse.join();
  Orb parts;
  orb.finish(&parts.kps, &parts.desc);
  expectSame(whole, parts);
  int coarse_octaves = 0;
  for (const cv::KeyPoint& k : parts.kps) coarse_octaves += k.octave >= split;
  EXPECT_GT(coarse_octaves, 0);
}

TEST(Orb, TheCoarseLevelsHoldAtMostHalfOfThePyramidsPixels) {
  for (float scale_factor : {1.2f, 1.5f, 2.0f}) {
    OrbOptions o;
    o.scale_factor = scale_factor;
    const cv::Mat img = test::blobImage({640, 480}, 37);
    const OrbExtraction orb(img, cv::Mat(), o);
    const std::vector<float> scales = orbLevelScales(o);
    std::vector<double> pixels;
    for (int l = 0; l < orb.levels(); ++l) pixels.push_back(640.0 * 480.0 / (scales[l] * scales[l]));
    const double total = std::accumulate(pixels.begin(), pixels.end(), 0.0);
    const int split = orb.coarseLevelsStart();
    ASSERT_GT(split, 0);
    ASSERT_LT(split, orb.levels());
    EXPECT_LE(std::accumulate(pixels.begin() + split, pixels.end(), 0.0), 0.51 * total) << scale_factor;
    EXPECT_GT(std::accumulate(pixels.begin() + split - 1, pixels.end(), 0.0), 0.49 * total) << scale_factor;
  }
  EXPECT_EQ(OrbExtraction(cv::Mat(), cv::Mat(), OrbOptions()).levels(), 0);
}

TEST(Orb, AcceptsColourRejectsBadInput) {
  const cv::Mat grey = test::blobImage({320, 240}, 29);
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  const Orb a = run(grey), b = run(bgr);
  ASSERT_EQ(a.kps.size(), b.kps.size());
  EXPECT_EQ(cv::norm(a.desc, b.desc, cv::NORM_HAMMING), 0.0);

  std::vector<cv::KeyPoint> k;
  cv::Mat d;
  cv::Mat f32;
  grey.convertTo(f32, CV_32F);
  EXPECT_THROW(extractOrb(f32, cv::Mat(), OrbOptions(), &k, &d), DataError);
  EXPECT_THROW(extractOrb(grey, cv::Mat(10, 10, CV_8U, cv::Scalar(255)), OrbOptions(), &k, &d), DataError);
  EXPECT_THROW(extractOrb(grey, cv::Mat(grey.size(), CV_16U, cv::Scalar(1)), OrbOptions(), &k, &d), DataError);
  OrbOptions bad;
  bad.scale_factor = 1.0f;
  EXPECT_THROW(extractOrb(grey, cv::Mat(), bad, &k, &d), ConfigError);
  bad = OrbOptions();
  bad.min_fast_threshold = bad.fast_threshold + 1;
  EXPECT_THROW(bad.validate(), ConfigError);
}

}  // namespace
}  // namespace plslam
