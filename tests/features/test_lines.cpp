#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "features/line_extractor.h"
#include "features/matching.h"
#include "synthetic_images.h"

namespace plslam {
namespace {

using Eigen::Vector2d;

double pointLineDistance(const Vector2d& x, const Vector2d& a, const Vector2d& b) {
  const Vector2d d = (b - a).normalized();
  return std::abs((x - a).x() * d.y() - (x - a).y() * d.x());
}

// Endpoint error of `s` against the truth (a, b), either orientation.
double endpointError(const LineSegment2D& s, const Vector2d& a, const Vector2d& b) {
  return std::min(std::max((s.p - a).norm(), (s.q - b).norm()), std::max((s.p - b).norm(), (s.q - a).norm()));
}

TEST(Lines, MergeJoinsCollinearFragments) {
  const Vector2d a(40, 100), b(440, 180);
  const Vector2d u = (b - a).normalized(), n(-u.y(), u.x());
  std::vector<LineSegment2D> segs;
  // Five fragments of a-b with 6-pixel gaps, small offsets and angle noise.
  const double len = (b - a).norm(), piece = (len - 4 * 6) / 5;
  for (int i = 0; i < 5; ++i) {
    const double t0 = i * (piece + 6), t1 = t0 + piece;
    const double off0 = 0.3 * ((i % 2) ? 1 : -1), off1 = -0.2 * ((i % 3) ? 1 : -1);
    segs.push_back(LineSegment2D::fromEndpoints(a + t0 * u + off0 * n, a + t1 * u + off1 * n));
  }
  // Not fragments of it: a parallel edge 10 px away, the opposite polarity on the same line
  // (the other side of a thin bar), the same line after a 60 px gap, and a crossing line.
  segs.push_back(LineSegment2D::fromEndpoints(a + 10 * n + 20 * u, b + 10 * n - 20 * u));
  segs.push_back(LineSegment2D::fromEndpoints(a + 100 * u, a + 50 * u));
  segs.push_back(LineSegment2D::fromEndpoints(b + 60 * u, b + 160 * u));
  segs.push_back(LineSegment2D::fromEndpoints({200, 40}, {260, 260}));

  const std::vector<LineSegment2D> out = mergeSegments(segs, LineOptions());
  ASSERT_EQ(out.size(), 5u);
  // Longest first: the joined one.
  EXPECT_LT(endpointError(out[0], a, b), 0.5);
  EXPECT_NEAR(out[0].length, len, 0.5);
  for (size_t i = 1; i < out.size(); ++i) EXPECT_LE(out[i].length, out[i - 1].length);
  // Length and angle are kept consistent with the endpoints.
  for (const LineSegment2D& s : out) {
    EXPECT_NEAR(s.length, (s.q - s.p).norm(), 1e-3);
    EXPECT_NEAR(s.angle, std::atan2(s.q.y() - s.p.y(), s.q.x() - s.p.x()), 1e-5);
  }
  // With a larger gap allowed, the far piece joins too.
  LineOptions wide;
  wide.merge_gap_px = 70;
  EXPECT_EQ(mergeSegments(segs, wide).size(), 4u);
}

// Directions are bucketed by angle: fragments pointing just either side of 180 degrees lie
// in the first and the last bucket, and must still be tried against each other.
TEST(Lines, MergeJoinsFragmentsWhoseDirectionsStraddleTheAngleWrap) {
  const double tilt = 0.5 * CV_PI / 180.0;  // each fragment 0.5 degrees off the -x axis
  const Vector2d start(400, 200);
  const Vector2d d1(-std::cos(tilt), std::sin(tilt)), d2(-std::cos(tilt), -std::sin(tilt));
  std::vector<LineSegment2D> segs;
  segs.push_back(LineSegment2D::fromEndpoints(start, start + 100 * d1));
  const Vector2d second = start + 100 * d1 + Vector2d(-4, 0);
  segs.push_back(LineSegment2D::fromEndpoints(second, second + 80 * d2));
  ASSERT_GT(std::atan2(segs[0].q.y() - segs[0].p.y(), segs[0].q.x() - segs[0].p.x()), 0.99 * CV_PI);
  ASSERT_LT(std::atan2(segs[1].q.y() - segs[1].p.y(), segs[1].q.x() - segs[1].p.x()), -0.99 * CV_PI);
  const std::vector<LineSegment2D> out = mergeSegments(segs, LineOptions());
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].length, 184.0, 1.0);
}

TEST(Lines, DetectionJoinsTheFragmentsOfADrawnEdge) {
  // A dark slanted band whose edges are cut by small bright discs: LSD returns pieces.
  cv::Mat img(480, 640, CV_8U, cv::Scalar(200));
  const std::vector<cv::Point> band = {{60, 150}, {580, 260}, {580, 300}, {60, 190}};
  cv::fillConvexPoly(img, band, cv::Scalar(40), cv::LINE_AA);
  for (int i = 1; i < 8; ++i) {
    const double t = i / 8.0;
    cv::circle(img, cv::Point(int(60 + t * 520), int(150 + t * 110)), 3, cv::Scalar(200), -1, cv::LINE_AA);
    cv::circle(img, cv::Point(int(60 + t * 520), int(190 + t * 110)), 3, cv::Scalar(200), -1, cv::LINE_AA);
  }
  for (double scale : {0.5, 1.0}) {
    LineOptions o;
    o.detect_scale = scale;
    LineStats st;
    const std::vector<LineSegment2D> lines = detectLines(img, cv::Mat(), o, &st);
    EXPECT_GT(st.detected, st.merged + 8) << "LSD should have returned the edges in pieces";
    // The top edge (a filled polygon's boundary lies about half a pixel outside its vertices).
    const Vector2d a(60, 149.5), b(580, 259.5);
    int found = 0;
    for (const LineSegment2D& s : lines)
      if (pointLineDistance(0.5 * (s.p + s.q), a, b) < 2 && s.length > 400) {
        ++found;
        EXPECT_LT(endpointError(s, a, b), 2.0) << "scale " << scale << ": " << s.p.transpose() << " - " << s.q.transpose();
        EXPECT_LT(pointLineDistance(s.p, a, b), 1.0);
        EXPECT_LT(pointLineDistance(s.q, a, b), 1.0);
      }
    EXPECT_EQ(found, 1) << "scale " << scale;
  }
}

TEST(Lines, ShortSegmentsAreDropped) {
  cv::Mat img(480, 640, CV_8U, cv::Scalar(200));
  cv::rectangle(img, cv::Rect(40, 300, 560, 60), cv::Scalar(30), -1);
  for (int i = 0; i < 12; ++i) cv::rectangle(img, cv::Rect(50 + 45 * i, 80 + 9 * i, 14, 14), cv::Scalar(30), -1);
  LineOptions o;
  LineStats st;
  const std::vector<LineSegment2D> lines = detectLines(img, cv::Mat(), o, &st);
  const double min_len = o.min_length_ratio * std::hypot(640, 480);
  for (const LineSegment2D& s : lines) EXPECT_GE(s.length, min_len);
  EXPECT_LT(st.long_enough, st.unmasked) << "the small squares' edges were there and dropped";
  int long_edges = 0;
  for (const LineSegment2D& s : lines) long_edges += s.length > 500;
  EXPECT_EQ(long_edges, 2);  // the long band's top and bottom
  // The stages only ever remove.
  EXPECT_GE(st.detected, st.merged);
  EXPECT_GE(st.merged, st.unmasked);
  EXPECT_GE(st.unmasked, st.long_enough);
  EXPECT_GE(st.long_enough, st.kept);
  EXPECT_EQ(st.kept, static_cast<int>(lines.size()));
}

TEST(Lines, CountCapKeepsTheLongest) {
  const cv::Mat img = test::structureImage({640, 480}, 31);
  LineOptions all;
  all.max_lines = 10000;
  const std::vector<LineSegment2D> full = detectLines(img, cv::Mat(), all);
  ASSERT_GT(full.size(), 25u);
  LineOptions capped;
  capped.max_lines = 12;
  LineStats st;
  const std::vector<LineSegment2D> top = detectLines(img, cv::Mat(), capped, &st);
  ASSERT_EQ(top.size(), 12u);
  EXPECT_EQ(st.kept, 12);
  EXPECT_EQ(st.long_enough, static_cast<int>(full.size()));
  for (size_t i = 0; i < top.size(); ++i) {
    EXPECT_EQ(top[i].p, full[i].p);
    EXPECT_EQ(top[i].q, full[i].q);
    if (i > 0) {
      EXPECT_LE(top[i].length, top[i - 1].length);
    }
  }
  EXPECT_LE(full[12].length, top.back().length);
}

TEST(Lines, MaskClipsAndDrops) {
  cv::Mat img(480, 640, CV_8U, cv::Scalar(200));
  cv::rectangle(img, cv::Rect(40, 200, 560, 50), cv::Scalar(30), -1);    // crosses the boundary
  cv::rectangle(img, cv::Rect(420, 330, 160, 80), cv::Scalar(30), -1);   // entirely forbidden
  cv::Mat mask(img.size(), CV_8U, cv::Scalar(255));
  mask(cv::Rect(400, 0, 240, 480)).setTo(0);
  LineStats st;
  const std::vector<LineSegment2D> lines = detectLines(img, mask, LineOptions(), &st);
  ASSERT_FALSE(lines.empty());
  int clipped = 0;
  for (const LineSegment2D& s : lines) {
    const int n = static_cast<int>(std::ceil(s.length)) + 1;
    for (int k = 0; k < n; ++k) {
      const Vector2d x = s.p + (s.q - s.p) * (double(k) / (n - 1));
      ASSERT_NE(mask.at<uint8_t>(int(std::lround(x.y())), int(std::lround(x.x()))), 0) << x.transpose();
    }
    if (s.length > 300) {
      ++clipped;
      EXPECT_NEAR(std::max(s.p.x(), s.q.x()), 399, 1.5);
    }
  }
  EXPECT_EQ(clipped, 2);
  EXPECT_LT(st.unmasked, st.merged);

  EXPECT_TRUE(detectLines(img, cv::Mat::zeros(img.size(), CV_8U), LineOptions()).empty());
}

TEST(Lines, ClipSegmentKeepsTheLongestAllowedStretch) {
  cv::Mat mask(100, 200, CV_8U, cv::Scalar(255));
  mask(cv::Rect(60, 0, 10, 100)).setTo(0);
  LineSegment2D s = LineSegment2D::fromEndpoints({10, 50}, {190, 50});
  ASSERT_TRUE(clipSegmentToMask(mask, &s));
  EXPECT_NEAR(s.p.x(), 70, 1.0);
  EXPECT_NEAR(s.q.x(), 190, 1e-9);
  EXPECT_NEAR(s.length, 120, 1.0);
  LineSegment2D inside = LineSegment2D::fromEndpoints({62, 10}, {67, 90});
  EXPECT_FALSE(clipSegmentToMask(mask, &inside));
  LineSegment2D free = LineSegment2D::fromEndpoints({80, 10}, {180, 90});
  const LineSegment2D before = free;
  ASSERT_TRUE(clipSegmentToMask(mask, &free));
  EXPECT_EQ(free.p, before.p);
  EXPECT_EQ(free.q, before.q);
}

TEST(Lines, LbdDescribesEverySegment) {
  const cv::Mat img = test::structureImage({640, 480}, 37);
  const std::vector<LineSegment2D> lines = detectLines(img, cv::Mat(), LineOptions());
  ASSERT_GT(lines.size(), 10u);
  const cv::Mat d = describeLines(img, lines, LineOptions());
  ASSERT_EQ(d.rows, static_cast<int>(lines.size()));
  ASSERT_EQ(d.cols, 32);
  ASSERT_EQ(d.type(), CV_8U);
  for (int i = 0; i < d.rows; ++i) EXPECT_GT(cv::countNonZero(d.row(i)), 0) << "row " << i;
  // Segments built by hand: across the border, tiny, degenerate, reversed.
  std::vector<LineSegment2D> own = {LineSegment2D::fromEndpoints({-20, 5}, {700, 30}),
                                    LineSegment2D::fromEndpoints({100, 100}, {101, 100}),
                                    LineSegment2D::fromEndpoints({50, 50}, {50, 50}), lines[0],
                                    LineSegment2D::fromEndpoints(lines[0].q, lines[0].p)};
  const cv::Mat d2 = describeLines(img, own, LineOptions());
  ASSERT_EQ(d2.rows, static_cast<int>(own.size()));
  EXPECT_EQ(cv::norm(d2.row(3), d.row(0), cv::NORM_HAMMING), 0.0) << "a row does not depend on the others";
  EXPECT_GT(cv::norm(d2.row(4), d.row(0), cv::NORM_HAMMING), 30.0) << "the direction matters";
  EXPECT_EQ(describeLines(img, {}, LineOptions()).rows, 0);
}

TEST(Lines, LbdIsStableUnderShiftAndDistinctive) {
  const cv::Mat big = test::structureImage({720, 560}, 41);
  const int dx = 17, dy = -11;
  const auto [a, b] = test::shiftedPair(big, {640, 480}, dx, dy);
  const std::vector<LineSegment2D> la = detectLines(a, cv::Mat(), LineOptions());
  std::vector<LineSegment2D> lb;
  for (const LineSegment2D& s : la) lb.push_back(LineSegment2D::fromEndpoints(s.p - Vector2d(dx, dy), s.q - Vector2d(dx, dy)));
  // At full scale the shifted support regions see exactly the same pixels; at half scale
  // the odd shift changes the resampling a little.
  LineOptions full;
  full.lbd_scale = 1.0;
  const cv::Mat da = describeLines(a, la, full), db = describeLines(b, lb, full);
  const cv::Mat ha = describeLines(a, la, LineOptions()), hb = describeLines(b, lb, LineOptions());
  int checked = 0;
  for (size_t i = 0; i < la.size(); ++i) {
    // Away from both images' borders the support regions see the same pixels.
    const auto inside = [](const LineSegment2D& s) {
      const double m = 40;
      return std::min({s.p.x(), s.q.x(), s.p.y(), s.q.y()}) > m && std::max(s.p.x(), s.q.x()) < 640 - m &&
             std::max(s.p.y(), s.q.y()) < 480 - m;
    };
    if (!inside(la[i]) || !inside(lb[i])) continue;
    ++checked;
    EXPECT_LE(hammingDistance(da.ptr<uint8_t>(int(i)), db.ptr<uint8_t>(int(i))), 8) << "line " << i;
    EXPECT_LE(hammingDistance(ha.ptr<uint8_t>(int(i)), hb.ptr<uint8_t>(int(i))), 30) << "line " << i;
  }
  EXPECT_GT(checked, 5);
  // Different lines are far apart on average.
  double sum = 0;
  int pairs = 0;
  for (int i = 0; i < da.rows; ++i)
    for (int j = i + 1; j < da.rows; ++j, ++pairs)
      sum += hammingDistance(da.ptr<uint8_t>(i), da.ptr<uint8_t>(j)) + hammingDistance(ha.ptr<uint8_t>(i), ha.ptr<uint8_t>(j));
  EXPECT_GT(sum / (2 * pairs), 60.0);
}

TEST(Lines, DeterministicAndEmptyInputs) {
  const cv::Mat img = test::structureImage({640, 480}, 43);
  LineStats s1, s2;
  const auto l1 = detectLines(img, cv::Mat(), LineOptions(), &s1);
  const auto l2 = detectLines(img.clone(), cv::Mat(), LineOptions(), &s2);
  ASSERT_EQ(l1.size(), l2.size());
  for (size_t i = 0; i < l1.size(); ++i) {
    EXPECT_EQ(l1[i].p, l2[i].p);
    EXPECT_EQ(l1[i].q, l2[i].q);
  }
  EXPECT_EQ(s1.detected, s2.detected);
  EXPECT_EQ(cv::norm(describeLines(img, l1, LineOptions()), describeLines(img, l2, LineOptions()), cv::NORM_HAMMING), 0.0);

  for (const cv::Mat& m : {cv::Mat(), cv::Mat(cv::Mat::zeros(10, 10, CV_8U)), cv::Mat(cv::Mat::zeros(480, 640, CV_8U)),
                           cv::Mat(cv::Mat::zeros(1, 640, CV_8U)), test::blobImage({12, 12}, 1, 10)}) {
    LineStats st;
    st.detected = 99;
    EXPECT_TRUE(detectLines(m, cv::Mat(), LineOptions(), &st).empty()) << m.cols << "x" << m.rows;
    EXPECT_EQ(st.detected, 0);
    EXPECT_EQ(st.kept, 0);
  }
}

TEST(Lines, RejectsBadInput) {
  const cv::Mat img = test::structureImage({320, 240}, 47);
  EXPECT_THROW(detectLines(img, cv::Mat(5, 5, CV_8U, cv::Scalar(255)), LineOptions()), DataError);
  cv::Mat f32;
  img.convertTo(f32, CV_32F);
  EXPECT_THROW(detectLines(f32, cv::Mat(), LineOptions()), DataError);
  LineOptions bad;
  bad.detect_scale = 0;
  EXPECT_THROW(detectLines(img, cv::Mat(), bad), ConfigError);
  bad = LineOptions();
  bad.max_lines = -1;
  EXPECT_THROW(bad.validate(), ConfigError);
  bad = LineOptions();
  bad.detector = "hough";
  EXPECT_THROW(detectLines(img, cv::Mat(), bad), ConfigError);
}

TEST(Lines, BothDetectorsFindTheEdgeWithTheBrighterSideOnTheLeft) {
  // A dark band on a bright background: its top edge has the bright side above. The merge
  // and LBD rely on every detector giving the same direction for the same contrast.
  cv::Mat img(480, 640, CV_8U, cv::Scalar(200));
  cv::fillConvexPoly(img, std::vector<cv::Point>{{60, 150}, {580, 260}, {580, 300}, {60, 190}}, cv::Scalar(40), cv::LINE_AA);
  const Vector2d a(60, 149.5), b(580, 259.5);
  for (const char* detector : {"lsd", "fld"}) {
    LineOptions o;
    o.detector = detector;
    int found = 0;
    for (const LineSegment2D& s : detectLines(img, cv::Mat(), o)) {
      if (pointLineDistance(0.5 * (s.p + s.q), a, b) > 2 || s.length < 400) continue;
      ++found;
      EXPECT_LT(endpointError(s, a, b), 3.0) << detector << ": " << s.p.transpose() << " - " << s.q.transpose();
      // Walking p -> q, the left side in image axes (y down) is (dy, -dx): probe there.
      const Vector2d d = s.q - s.p;
      const Vector2d left(d.y(), -d.x());
      const Vector2d mid = 0.5 * (s.p + s.q);
      const Vector2d probe = mid + 5 * left.normalized();
      EXPECT_GT(img.at<uint8_t>(int(std::lround(probe.y())), int(std::lround(probe.x()))), 120) << detector;
    }
    EXPECT_EQ(found, 1) << detector;
  }
}

}  // namespace
}  // namespace plslam
