#include "servo_sim/tag_room.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "calibration/render.h"

namespace plslam {

namespace {

calib::Target singleTag(const TagRoomOptions& o) {
  calib::Target t;
  t.kind = calib::TargetKind::kAprilGrid;
  t.cols = t.rows = 1;
  t.size = o.tag_size;
  t.first_id = o.tag_id;
  t.validate();
  return t;
}

synth::Scene staticRoom(const TagRoomOptions& o) {
  synth::SceneOptions s;
  s.width = o.width;
  s.height = o.height;
  s.seed = o.seed;
  s.frames = 1;  // views are rendered at the servo's poses, not along the scene's path
  return synth::makeScene(synth::SceneKind::kStatic, s);
}

}  // namespace

TagRoom::TagRoom(const SE3& T_room_tag, const TagRoomOptions& options)
    : options_(options), scene_(staticRoom(options)), target_(singleTag(options)), T_room_tag_(T_room_tag) {}

SE3 TagRoom::onEastWall(double y, double z) {
  // Columns: the tag axes in the room (x right as seen from the room = -y, y down = -z, z into the wall = +x).
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  // A hair in front of the wall so that the wall's own depth matches the tag plane's.
  return SE3(Eigen::Quaterniond(R), Eigen::Vector3d(2.999, y, z));
}

synth::RenderedFrame TagRoom::render(const SE3& T_room_c, TimeNs t_ns, uint64_t noise_stream) const {
  synth::RenderedFrame frame = synth::renderView(scene_, T_room_c, t_ns, noise_stream);
  drawTag(T_room_c, &frame);
  return frame;
}

void TagRoom::drawTag(const SE3& T_room_c, synth::RenderedFrame* frame) const {
  const SE3 T_c_board = T_room_c.inverse() * T_room_tag_ * target_.boardFromTarget().inverse();
  const SE3 T_board_c = T_c_board.inverse();
  if (T_board_c.translation().z() >= 0) return;  // the camera is behind the wall: the printed face is away from it
  const Eigen::Vector3d n = T_c_board.rotation().col(2);
  const double n_o = n.dot(T_c_board.translation());
  const cv::Rect2d area = target_.printedArea();
  const PinholeCamera& cam = camera();
  cv::Mat mask(frame->bgr.size(), CV_8U, cv::Scalar(0));
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      const double denom = n.dot(ray);
      if (std::abs(denom) < 1e-12) continue;
      const double z = n_o / denom;  // the ray's z is 1: z is the depth of the plane along it
      if (!(z > 0)) continue;
      const Eigen::Vector3d q = T_board_c * (z * ray);
      if (!area.contains(cv::Point2d(q.x(), q.y()))) continue;
      const float seen = frame->depth_m.at<float>(v, u);
      if (std::isfinite(seen) && std::abs(seen - z) > 0.03 + 0.03 * z) continue;  // something in front of it
      mask.at<uint8_t>(v, u) = 255;
    }
  }
  if (cv::countNonZero(mask) == 0) return;
  calib::RenderOptions ro;
  ro.supersampling = 3;
  cv::Mat printed;
  cv::cvtColor(calib::renderTarget(target_, cam, T_c_board, ro), printed, cv::COLOR_GRAY2BGR);
  printed.copyTo(frame->bgr, mask);
}

}  // namespace plslam
