// Deterministic images for the feature tests, drawn with OpenCV (cv::RNG is seeded and
// platform-independent).
#pragma once

#include <opencv2/imgproc.hpp>
#include <vector>

namespace plslam::test {

/// Random filled circles and rectangles of random grey levels: corners everywhere.
inline cv::Mat blobImage(cv::Size size, uint64_t seed, int blobs = -1, double contrast = 1.0) {
  cv::RNG rng(seed);
  cv::Mat img(size, CV_8U, cv::Scalar(128));
  if (blobs < 0) blobs = size.area() / 500;
  for (int i = 0; i < blobs; ++i) {
    const cv::Point c(rng.uniform(0, size.width), rng.uniform(0, size.height));
    const int r = rng.uniform(2, 12);
    const int grey = static_cast<int>(128 + contrast * (rng.uniform(0, 256) - 128));
    if (i % 2) cv::circle(img, c, r, cv::Scalar(grey), -1);
    else cv::rectangle(img, cv::Rect(c.x - r, c.y - r / 2, 2 * r, r), cv::Scalar(grey), -1);
  }
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}

/// Dark rectangles and slanted bars on a light background: long straight edges of many
/// lengths and directions.
inline cv::Mat structureImage(cv::Size size, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat img(size, CV_8U, cv::Scalar(210));
  for (int i = 0; i < 14; ++i) {
    const int w = rng.uniform(30, size.width / 3), h = rng.uniform(20, size.height / 3);
    const cv::Point c(rng.uniform(w / 2, size.width - w / 2), rng.uniform(h / 2, size.height - h / 2));
    const cv::RotatedRect rr(c, cv::Size2f(float(w), float(h)), float(rng.uniform(-40.0, 40.0)));
    cv::Point2f pts[4];
    rr.points(pts);
    std::vector<cv::Point> poly(pts, pts + 4);
    cv::fillConvexPoly(img, poly, cv::Scalar(rng.uniform(0, 140)), cv::LINE_AA);
  }
  return img;
}

/// Two same-size crops of `big`: the content at (x, y) of the first is at (x - dx, y - dy)
/// of the second, i.e. the second is the first shifted by (-dx, -dy).
inline std::pair<cv::Mat, cv::Mat> shiftedPair(const cv::Mat& big, cv::Size size, int dx, int dy) {
  const int x0 = std::max(0, -dx) + 8, y0 = std::max(0, -dy) + 8;
  return {big(cv::Rect(x0, y0, size.width, size.height)).clone(),
          big(cv::Rect(x0 + dx, y0 + dy, size.width, size.height)).clone()};
}

}  // namespace plslam::test
