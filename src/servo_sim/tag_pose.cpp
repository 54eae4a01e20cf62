#include "servo_sim/tag_pose.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace plslam {

namespace {

calib::Target singleTag(int tag_id, double tag_size) {
  calib::Target t;
  t.kind = calib::TargetKind::kAprilGrid;
  t.cols = t.rows = 1;
  t.size = tag_size;
  t.first_id = tag_id;
  t.validate();
  return t;
}

// The servo wants any view of the whole tag: no verdicts on sharpness or coverage.
calib::DetectionOptions anyView() {
  calib::DetectionOptions o;
  o.min_sharpness = 0;
  o.min_tags = 1;
  o.min_area_fraction = 0;
  return o;
}

}  // namespace

TagPoseDetector::TagPoseDetector(const PinholeCamera& camera, int tag_id, double tag_size)
    : camera_(camera), tag_size_(tag_size), detector_(singleTag(tag_id, tag_size), anyView()) {}

std::optional<SE3> TagPoseDetector::detect(const cv::Mat& image) const {
  const calib::ViewResult view = detector_.detect(image);
  if (view.observation.size() != 4) return std::nullopt;
  // The corners in the tag frame, in the library's order (bottom-left, bottom-right,
  // top-right, top-left as printed, y down): the order SOLVEPNP_IPPE_SQUARE expects.
  const Eigen::Vector3d centre = detector_.target().boardFromTarget().translation();
  std::vector<cv::Point3f> object;
  for (const cv::Point3f& p : view.observation.object)
    object.emplace_back(p.x - static_cast<float>(centre.x()), p.y - static_cast<float>(centre.y()), 0.f);
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(object, view.observation.image, cv::Mat(camera_.K()), camera_.distCoeffs(), rvec, tvec, false,
                    cv::SOLVEPNP_IPPE_SQUARE))
    return std::nullopt;
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  cv::cv2eigen(R, Re);
  return SE3(Eigen::Quaterniond(Re).normalized(), Eigen::Vector3d(tvec[0], tvec[1], tvec[2]));
}

}  // namespace plslam
